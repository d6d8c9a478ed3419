#!/usr/bin/env bash
# Where the whole driver run's time goes (docs/BENCHMARKS.md, "Profile of
# the whole run"): an es_synth waterfall (default 320x240, 120 frames),
# then `eulersplat --profile` on it, then two tables: wall and CPU seconds
# per stage (OUT/timings.json) and Stage 3's iteration by part (render for
# the fit, the loop's second render, fields, Euler chain, backward, Adam,
# densification, evaluation; es_train's "profile by part"). The load
# average at the start and end says whether the machine was idle. Not part
# of the tests.
#
#   benchmarks/profile_driver.sh [options]
#     --work DIR            scratch folder (default /tmp/es_profile_driver)
#     --threads N           the driver's --threads (default 2)
#     --frames N --width W --height H   the clip (120, 320, 240)
#     --preset P            auto, quick or paper (default quick)
#     --static_iterations N / --joint_iterations N
#                           override the preset's (shorter runs: the
#                           per-iteration figures stay comparable)
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/options.sh
source scripts/lib/time_v.sh
work=/tmp/es_profile_driver; threads=2; frames=120; width=320; height=240
preset=quick; static_iterations=""; joint_iterations=""
parse_options \
  "work threads frames width height preset static_iterations joint_iterations" \
  "" "$@"
require_numbers "$threads" "$frames" "$width" "$height"
overrides=()
[[ -z "$static_iterations" ]] ||
  overrides+=(--static_iterations "$static_iterations")
[[ -z "$joint_iterations" ]] ||
  overrides+=(--joint_iterations "$joint_iterations")
require_apps es_synth eulersplat
bin=build/bin

mkdir -p "$work"
scene="$work/scene_${width}x${height}x${frames}"
if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
  echo "[profile] es_synth -> $scene"
  "$bin/es_synth" --out "$scene" --preset waterfall --frames "$frames" \
      --width "$width" --height "$height" > "$work/synth.log"
fi
run="$work/run"
rm -rf "$run"
load_start=$(load)
echo "[profile] eulersplat --preset $preset --threads $threads ${overrides[*]}" \
     "(load average $load_start at the start, $(nproc) cores)"
"$bin/eulersplat" --scene "$scene" --out "$run" --preset "$preset" \
    --threads "$threads" --profile "${overrides[@]}" > "$work/driver.log" 2>&1 \
  || { tail -30 "$work/driver.log"; exit 1; }
load_end=$(load)

python3 - "$run/timings.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
print(f"\npreset {t['preset']}, {t['threads']} thread(s)")
if "preset_auto" in t:
    print(f"  auto: {t['preset_auto']['why']}")
print(f"{'stage':48s} {'wall s':>8s} {'CPU s':>8s}")
for s in t["stages"]:
    note = " (skipped)" if s["skipped"] else ""
    print(f"{s['name'] + note:48s} {s['seconds']:8.1f} {s['cpu_seconds']:8.1f}")
print(f"{'total':48s} {t['total_seconds']:8.1f}")
PY
echo
echo "Stage 3 (es_train), by part:"
awk '/^profile: es_train/ {on = 1} on && /^profile by part:/ {p = 1}
     p {print} p && /^the loop texture pass/ {exit}' "$work/driver.log"
echo
echo "Stage 1 (es_static), by part:"
awk '/^profile: es_static/ {on = 1} on && /^profile by part:/ {p = 1}
     p && /^total/ {print; exit} p {print}' "$work/driver.log"
echo
echo "load average $load_start at the start, $load_end at the end;" \
     "full log: $work/driver.log"
