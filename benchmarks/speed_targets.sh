#!/usr/bin/env bash
# Measures every speed target of the CPU-speed work (docs/BENCHMARKS.md,
# "Speed targets"; every run so far: docs/benchmarks/speed-targets.md) in
# one go, for a rerun on an idle machine:
#   1. rasterizer forward+backward Gaussian-pixel pairs/s (2 threads, float,
#      each instruction set) at 320x240 / 10k and 1168x880 / 300k;
#   2. a static (Stage 1) and a joint (Stage 3) iteration at the same
#      Gaussian count (--profile's ms per iteration) on a 320x240, 120-frame
#      es_synth waterfall: es_static, then es_train from its model with the
#      fields (joint) and with --static_only (same Gaussians, no fields),
#      one frame per iteration (the water energy loss, on by default, trains
#      on frame pairs and does about three times the work per iteration);
#   3. the README's default run (scripts/run_default.sh's scene and
#      command) end to end, animation included;
#   4. the quick preset end to end on the 320x240, 120-frame scene.
# Wall times come from /usr/bin/time; each line carries the load average
# at its start (figures taken above ~0.5 are not idle figures). Not part of
# the tests.
#
#   benchmarks/speed_targets.sh [options]
#     --work DIR       scratch folder (default /tmp/es_speed_targets)
#     --threads N      OMP threads (default 2)
#     --skip LIST      comma-separated steps to skip: raster,iterations,
#                      default,quick
#     --static_its N   es_static iterations before the joint runs (300)
#     --joint_its N    iterations of each es_train run (150)
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/options.sh
source scripts/lib/time_v.sh
work=/tmp/es_speed_targets ; threads=2 ; skip="" ; static_its=300
joint_its=150
parse_options "work threads skip static_its joint_its" "" "$@"
require_numbers "$threads" "$static_its" "$joint_its"
bin=build/bin
require_apps bench_rasterizer es_synth es_static es_train eulersplat
require_time_v
mkdir -p "$work"
export OMP_NUM_THREADS="$threads"
skipped() { [[ ",$skip," == *",$1,"* ]]; }
# The "total" ms per iteration of a --profile table.
profile_ms() { awk '$1 == "total" {print $3}' "$1"; }
json_number() {
  sed -n "s/.*\"$2\": *\\([-0-9.eE+]*\\).*/\\1/p" "$1" | head -1; }

echo "[speed] $(date -u +%FT%TZ), $(nproc) CPUs, $threads threads, commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"

if ! skipped raster; then
  echo "[speed] 1. rasterizer forward+backward, float, $threads threads (load $(load))"
  "$bin/bench_rasterizer" --benchmark_min_time=1 --benchmark_filter="ForwardBackward/w:(320|1168)/h:(240|880)/n:(10000|300000)/threads:$threads/double:0/" \
      --benchmark_counters_tabular=true 2>/dev/null | grep -E "^BM_|^Benchmark" |
    awk '{print "  " $0}'
fi

scene="$work/scene320"
if ! skipped iterations || ! skipped quick; then
  if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
    echo "[speed] es_synth -> $scene (320x240, 120 frames)"
    "$bin/es_synth" --out "$scene" --preset waterfall --frames 120 \
        --width 320 --height 240 > "$work/synth.log"
  fi
fi

if ! skipped iterations; then
  echo "[speed] 2. static vs joint iteration at the same Gaussian count"
  s1="$work/stage1"
  l=$(load)
  "$bin/es_static" --scene "$scene" --out "$s1" --iterations "$static_its" \
      --densify=false --checkpoint_every 0 --eval_every 0 --log_every 0 \
      --profile > "$work/es_static.log" 2>&1 || { tail -5 "$work/es_static.log"; exit 1; }
  echo "  es_static (from seed points): $(profile_ms "$work/es_static.log") ms/iteration (load $l)"
  for mode in joint static_only; do
    extra=()
    [[ $mode == static_only ]] && extra=(--static_only)
    l=$(load)
    "$bin/es_train" --scene "$scene" --init "$s1" --out "$work/stage3_$mode" \
        --iterations "$joint_its" --no_flow_init --checkpoint_interval 0 \
        --eval_interval 0 --log_interval 0 --profile "${extra[@]}" \
        --motion_energy_weight 0 --detail_energy_weight 0 \
        --densify_water_interval 0 \
        > "$work/es_train_$mode.log" 2>&1 || { tail -5 "$work/es_train_$mode.log"; exit 1; }
    echo "  es_train $mode: $(profile_ms "$work/es_train_$mode.log") ms/iteration (load $l)"
  done
  j=$(profile_ms "$work/es_train_joint.log")
  s=$(profile_ms "$work/es_train_static_only.log")
  echo "  joint / static at $(sed -n 's/.*iterations, \([0-9]*\) Gaussians.*/\1/p' "$work/es_train_joint.log" | head -1) Gaussians: $(echo "$j / $s" | bc -l | cut -c1-5)x (target <= 1.5x)"
fi

run_driver() {  # name scene out extra-args...
  local name=$1 sc=$2 out=$3; shift 3
  local l; l=$(load)
  rm -rf "$out"
  /usr/bin/time -v -o "$out.time" "$bin/eulersplat" --scene "$sc" --out "$out" \
      "$@" > "$out.log" 2>&1 || { tail -5 "$out.log"; exit 1; }
  local eval_json="$out/eval/eval.json"
  echo "  $name: $(wall_s "$out.time") s wall, held-out PSNR $(json_number "$eval_json" psnr) dB (load $l)"
}

if ! skipped default; then
  echo "[speed] 3. the README's default run (quick preset, default scene)"
  dscene="$work/default_scene"
  [[ -d "$dscene/sparse/0" ]] || "$bin/es_synth" --out "$dscene" \
      --preset waterfall --frames 60 --width 160 --height 120 --detail 0.3 \
      --num_points 2000 > "$work/default_synth.log"
  run_driver default "$dscene" "$work/default"
fi

if ! skipped quick; then
  echo "[speed] 4. quick preset on the 320x240, 120-frame scene"
  run_driver quick320 "$scene" "$work/quick320" --preset quick
fi
