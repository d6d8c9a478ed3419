#!/usr/bin/env bash
# Automatic water masks scored against the true masks of synthetic presets,
# as the driver makes them with --masks auto: es_synth (exact poses), the
# mask probe (es_static without masks, the quick preset's half Stage 1:
# 300 iterations), then es_masks --truth. Prints one line per preset (IoU,
# precision, recall, water fraction, es_masks CPU seconds) and writes
# OUT/TAG.tsv. Scenes and probes are kept under OUT and reused, so a second
# run with other es_masks flags (or ES_MASKS=another es_masks binary)
# only reruns es_masks.
#
#   scripts/masks_benchmark.sh [--out DIR] [--presets "waterfall planks"]
#                              [--frames 120] [--width 320 --height 240]
#                              [--detail 1] [--tag NAME]
#                              [-- extra es_masks flags]
set -euo pipefail
cd "$(dirname "$0")/.."

out=out/masks_benchmark
presets="waterfall stream fountain droplets pathtraced planks"
frames=120
width=320
height=240
detail=1
tag=default
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --presets) presets=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --width) width=$2; shift 2 ;;
    --height) height=$2; shift 2 ;;
    --detail) detail=$2; shift 2 ;;
    --tag) tag=$2; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "masks_benchmark.sh: unknown argument '$1' (see --help)" >&2
       exit 2 ;;
  esac
done
bin=build/bin
masks_bin=${ES_MASKS:-$bin/es_masks}  # another build's, to compare
size="${width}x${height}x${frames}_d${detail}"
mkdir -p "$out/scenes" "$out/probes"
table="$out/$tag.tsv"
printf "preset\tiou\tprecision\trecall\twater_fraction\tcpu_s\n" > "$table"
for preset in $presets; do
  scene="$out/scenes/${preset}_$size"
  probe="$out/probes/${preset}_$size"
  if [[ ! -f "$scene/gt/settings.json" ]]; then
    rm -rf "$scene"
    "$bin/es_synth" --out "$scene" --preset "$preset" --frames "$frames" \
      --width "$width" --height "$height" --detail "$detail" > /dev/null
  fi
  if [[ ! -f "$probe/static.ply" ]]; then
    # The driver's probe on the quick preset (solvers/pipeline/stage_plan.cc).
    "$bin/es_static" --scene "$scene" --out "$probe" --iterations 300 \
      --mask_weight 0 --sh_degree 1 --sh_degree_interval 300 \
      --densify_from 100 --densify_interval 100 > "$probe.log" 2>&1
  fi
  run="$out/runs/$tag/${preset}_$size"
  rm -rf "$run"
  mkdir -p "$run"
  /usr/bin/time -f "%U %S" -o "$run/time.txt" \
    "$masks_bin" --scene "$scene" --static "$probe/static.ply" \
    --out "$run/masks" --truth "$scene/masks" "$@" > "$run/log.txt" 2>&1
  cpu=$(awk '{printf "%.1f", $1 + $2}' "$run/time.txt")
  python3 - "$run/masks_report.json" "$preset" "$cpu" >> "$table" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
t = r
print("\t".join([sys.argv[2]] + ["%.3f" % t.get(k, float("nan")) for k in
      ("mean_iou", "mean_precision", "mean_recall")] +
      ["%.3f" % r["water_fraction"], sys.argv[3]]))
EOF
  tail -1 "$table"
done
