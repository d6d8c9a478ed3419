#!/usr/bin/env bash
# The one command a newcomer runs: installs what is missing and builds
# (scripts/setup.sh), generates the embedded default scene with es_synth
# (once, into out/default_scene), then runs every stage with the preset
# auto picks (quick, exactly, for this small scene) into out/default and
# says where the results are. Re-running skips what is already done.
#
#   scripts/run_default.sh
#
# Environment: PRESET (default auto), SCENE and OUT to use other
# directories.
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
  "") ;;
  *) echo "run_default.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/.."

bash scripts/setup.sh
scene=${SCENE:-out/default_scene}
out=${OUT:-out/default}
preset=${PRESET:-auto}

if [[ -d "$scene/sparse/0" ]]; then
  echo "[default] scene $scene exists; not regenerating"
else
  echo "[default] generating the default scene into $scene"
  build/bin/es_synth --out "$scene" --preset waterfall --frames 60 \
    --width 160 --height 120 --detail 0.3 --num_points 2000
fi

build/bin/eulersplat --scene "$scene" --out "$out" --preset "$preset"

echo
echo "[default] looping video: $out/animate/animation.mp4"
echo "[default] metrics:       $out/eval/eval.json"
echo "[default] contact sheet: $out/contact_sheet.png"
