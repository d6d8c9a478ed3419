#!/usr/bin/env bash
# Stage 3 iteration vs Stage 1 iteration at the same Gaussian count, every
# default loss on (issue 45, item 2; docs/BENCHMARKS.md): an es_synth
# waterfall, es_static from its seed points (no densification, no
# held-out evaluation), then es_train from that model with its defaults
# (water densification off, so the count stays Stage 1's). Prints each
# run's "total" ms per iteration of its --profile table, its CPU seconds
# and the load average at its start, then Stage 3 / Stage 1 and Stage 3's
# parts (the wall-time ratio is the target's; on a loaded machine the CPU
# seconds' ratio is the steadier one). With --baseline, another build's
# es_train runs on the same model, alternating with this build's, and their model files are compared
# (cmp: "same" when the two builds' results are bit-identical). Not part
# of the tests.
#
#   benchmarks/stage3_ratio.sh [options]
#     --work DIR          scratch folder (default /tmp/es_stage3_ratio)
#     --threads N         --threads of both stages (default 2)
#     --width W --height H --frames N   the clip (224, 168, 60)
#     --static_its N      es_static iterations (default 300)
#     --joint_its N       es_train iterations per run (default 300: the
#                         losses keep what they compute from each input
#                         frame, so the first pass over the 54 training
#                         frames costs more than the rest of a long run)
#     --rounds N          es_train runs per build (default 1)
#     --baseline BIN      another build's bin folder to compare with
#     --train_flags "..." extra es_train flags of this build's runs only,
#                         e.g. "--loop_texture_interval 4"
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/options.sh
source scripts/lib/time_v.sh
work=/tmp/es_stage3_ratio; threads=2; width=224; height=168; frames=60
static_its=300; joint_its=300; rounds=1; baseline=""; train_flags=""
parse_options \
  "work threads width height frames static_its joint_its rounds baseline"\
" train_flags" \
  "" "$@"
require_numbers "$threads" "$width" "$height" "$frames" "$static_its" \
  "$joint_its" "$rounds"
require_apps es_synth es_static es_train
bin=build/bin
[[ -z "$baseline" || -x "$baseline/es_train" ]] ||
  { echo "stage3_ratio.sh: $baseline/es_train missing" >&2; exit 1; }

profile_ms() { awk '$1 == "total" {print $3; exit}' "$1"; }
user_sys_s() { awk '{printf "%.1f", $1 + $2}' "$1"; }
# CPU ms per iteration of a run: its CPU seconds (setup and the final
# evaluation included) over its iterations.
cpu_ms() { awk -v n="$2" '{printf "%.1f", 1000 * ($1 + $2) / n}' "$1"; }

echo "[ratio] $(date -u +%FT%TZ), $(nproc) CPUs, $threads threads," \
     "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)" \
     "${train_flags:+(this build with $train_flags)}"
mkdir -p "$work"
scene="$work/scene_${width}x${height}x${frames}"
if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
  "$bin/es_synth" --out "$scene" --preset waterfall --frames "$frames" \
      --width "$width" --height "$height" > "$work/synth.log"
fi

s1="$work/stage1"
l=$(load)
rm -rf "$s1"
/usr/bin/time -f "%U %S" -o "$work/stage1.time" \
  "$bin/es_static" --scene "$scene" --out "$s1" --iterations "$static_its" \
    --threads "$threads" --densify=false --checkpoint_every 0 \
    --eval_every 0 --log_every 0 --profile > "$work/stage1.log" 2>&1 ||
  { tail -5 "$work/stage1.log"; exit 1; }
stage1=$(profile_ms "$work/stage1.log")
echo "[ratio] Stage 1: $stage1 ms/iteration, $(user_sys_s "$work/stage1.time")" \
     "CPU s for $static_its iterations (load $l)"
stage1_cpu=$(cpu_ms "$work/stage1.time" "$static_its")

# stage3 NAME BIN [FLAG...]: one es_train run into $work/NAME; prints its
# line.
stage3() {
  local name=$1 b=$2 out="$work/$1"
  shift 2
  local l; l=$(load)
  rm -rf "$out"
  /usr/bin/time -f "%U %S" -o "$out.time" \
    "$b/es_train" --scene "$scene" --init "$s1" --out "$out" \
      --iterations "$joint_its" --threads "$threads" \
      --densify_water_interval 0 --checkpoint_interval 0 --eval_interval 0 \
      --log_interval 0 --seed 0 --profile "$@" > "$out.log" 2>&1 ||
    { tail -5 "$out.log"; exit 1; }
  echo "[ratio] Stage 3 ($name): $(profile_ms "$out.log") ms/iteration," \
       "$(user_sys_s "$out.time") CPU s for $joint_its iterations (load $l)"
}

for ((r = 1; r <= rounds; ++r)); do
  # shellcheck disable=SC2086  # the flags split into words
  stage3 "this_$r" "$bin" $train_flags
  [[ -z "$baseline" ]] || stage3 "baseline_$r" "$baseline"
done

gaussians=$(sed -n 's/.*iterations, \([0-9]*\) Gaussians.*/\1/p' \
              "$work/this_1.log" | head -1)
echo
echo "[ratio] at ${gaussians:-?} Gaussians, Stage 3 / Stage 1 (target <= 1.5x):"
for ((r = 1; r <= rounds; ++r)); do
  for name in this baseline; do
    [[ $name == baseline && -z "$baseline" ]] && continue
    echo "  $name, round $r: $(echo "$(profile_ms "$work/${name}_$r.log") /" \
         "$stage1" | bc -l | cut -c1-5)x in wall ms per iteration," \
         "$(echo "$(cpu_ms "$work/${name}_$r.time" "$joint_its") /" \
         "$stage1_cpu" | bc -l | cut -c1-5)x in CPU ms per iteration"
  done
done
if [[ -n "$baseline" ]]; then
  for f in canonical.ply motion_field.bin residual_field.bin loop.txt; do
    if cmp -s "$work/this_1/$f" "$work/baseline_1/$f"; then
      echo "  $f: same"
    else
      echo "  $f: differs"
    fi
  done
fi
echo
echo "Stage 3 by part (this build, round 1):"
awk '/^profile by part:/ {p = 1} p {print} p && /^the loop texture pass/ {exit}' \
    "$work/this_1.log"
