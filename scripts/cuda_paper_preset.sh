#!/usr/bin/env bash
# The whole paper preset on one GPU, for the CUDA backend's end-to-end
# figure (docs/BENCHMARKS.md, "GPU"): a synthetic 1168x880 waterfall of 300
# frames with exact poses and masks (es_synth), then the driver with
# --preset paper (10k static + 20k joint iterations, L = 15, full-size
# fields) and --device cuda. The driver prints each stage's wall time;
# /usr/bin/time the whole run's and its peak memory. Needs a build with
# the CUDA backend (build/, or BUILD) and an NVIDIA GPU.
#
#   scripts/cuda_paper_preset.sh [OUT]     (default out/paper_cuda)
#
# Environment: FRAMES (default 300), ANIMATE (default 0: train and
# evaluate only), BUILD (default build).
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
esac
cd "$(dirname "$0")/.."
out=${1:-out/paper_cuda}
build=${BUILD:-build}
frames=${FRAMES:-300}
animate=$([[ "${ANIMATE:-0}" == 1 ]] && echo true || echo false)

for bin in es_synth eulersplat; do
  [[ -x "$build/bin/$bin" ]] || {
    echo "cuda_paper_preset.sh: $build/bin/$bin missing: build with" \
         "cmake -S . -B $build -DES_CUDA=ON && cmake --build $build" >&2
    exit 1
  }
done
scene="$out/scene"
if [[ -d "$scene/sparse/0" ]]; then
  echo "[paper] scene $scene exists; not regenerating"
else
  echo "[paper] generating a 1168x880 waterfall of $frames frames"
  "$build/bin/es_synth" --out "$scene" --preset waterfall \
    --frames "$frames" --width 1168 --height 880
fi
/usr/bin/time -v "$build/bin/eulersplat" --scene "$scene" --out "$out/run" \
  --preset paper --device cuda --animate="$animate" 2>&1 |
  tee "$out/run.log"
grep -E "Elapsed|Maximum resident" "$out/run.log"
