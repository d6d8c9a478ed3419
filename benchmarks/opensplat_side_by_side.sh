#!/usr/bin/env bash
# es_static vs OpenSplat (CPU build against Debian's libtorch) on the same
# synthetic scene: same iterations, SH degree and schedule, no
# densification, the same thread count, one held-out frame, both timed by
# /usr/bin/time -v, runs interleaved (es, OpenSplat, es, ...) so a busy
# machine loads both alike. Not part of the tests; nothing is downloaded.
#
#   benchmarks/opensplat_side_by_side.sh [options]
#     --opensplat_src DIR  build OpenSplat from this source checkout (a
#                          clone of github.com/WebODM/OpenSplat) into
#                          WORK/opensplat-build first (needs libtorch-dev)
#     --opensplat BIN      an OpenSplat binary already built (default:
#                          WORK/opensplat-build/opensplat if present)
#     --work DIR           scratch folder (default /tmp/es_vs_opensplat)
#     --iterations N       training iterations of both (default 300)
#     --threads N          OMP / torch threads of both (default 2)
#     --runs N             interleaved runs of each (default 3)
#     --points N           seed points of the scene (default 7600)
#     --sh_degree N        maximum SH degree of both (default 3)
#     --es_static BIN      default: build/bin/es_static
#     --busy N             keep N other processes spinning on the CPU during
#                          every run (a shared machine; default 0)
#
# Prints one line per run (wall s, ms/iteration, user + sys CPU s, peak RSS
# MB, held-out PSNR, load average) and the medians.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/options.sh
source scripts/lib/time_v.sh
work=/tmp/es_vs_opensplat
opensplat_src="" ; opensplat="" ; iterations=300 ; threads=2 ; runs=3
points=7600 ; sh_degree=3 ; es_static=build/bin/es_static ; busy=0
parse_options \
  "opensplat_src opensplat work iterations threads runs points sh_degree es_static busy" \
  "" "$@"
require_numbers "$iterations" "$threads" "$runs" "$points" "$sh_degree" "$busy"
require_apps es_synth
[[ -x "$es_static" ]] || {
  echo "$es_static missing: run scripts/setup.sh" >&2; exit 1; }
require_time_v
command -v colmap > /dev/null || {
  echo "colmap missing (OpenSplat reads binary COLMAP models)" >&2; exit 1; }
mkdir -p "$work"

# The scene: 320x240 waterfall, 120 frames; frame 60 held out by both.
scene="$work/scene"
if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
  echo "[bench] es_synth -> $scene"
  build/bin/es_synth --out "$scene" --preset waterfall --frames 120 \
      --width 320 --height 240 --num_points "$points" > "$work/synth.log"
fi
held_out=$(ls "$scene/images" | sort | sed -n 61p)
echo "$held_out" > "$scene/split.txt"
# OpenSplat's copy: binary model, same images, no masks (neither run uses
# a mask term: es_static runs with --mask_weight 0).
os_scene="$work/scene_opensplat"
if [[ ! -f "$os_scene/sparse/0/images.bin" ]]; then
  mkdir -p "$os_scene/sparse/0"
  ln -sfn "$(realpath "$scene/images")" "$os_scene/images"
  colmap model_converter --input_path "$scene/sparse/0" \
      --output_path "$os_scene/sparse/0" --output_type BIN > /dev/null
fi

if [[ -n "$opensplat_src" ]]; then
  [[ -f "$opensplat_src/opensplat.cpp" ]] || { echo "$opensplat_src: not an OpenSplat checkout" >&2; exit 1; }
  echo "[bench] building OpenSplat (CPU) in $work/opensplat-build"
  cmake -S "$opensplat_src" -B "$work/opensplat-build" -DCMAKE_BUILD_TYPE=Release \
      -DGPU_RUNTIME=CPU > "$work/opensplat-cmake.log" 2>&1 \
      || { tail -20 "$work/opensplat-cmake.log"; exit 1; }
  cmake --build "$work/opensplat-build" -j"$threads" --target opensplat \
      > "$work/opensplat-build.log" 2>&1 \
      || { tail -30 "$work/opensplat-build.log"; exit 1; }
fi
[[ -z "$opensplat" && -x "$work/opensplat-build/opensplat" ]] &&
  opensplat="$work/opensplat-build/opensplat"

# The other jobs of a shared machine: busy loops, ended with the script.
busy_pids=()
trap 'kill "${busy_pids[@]}" 2> /dev/null || true' EXIT
for ((b = 0; b < busy; ++b)); do
  bash -c 'while :; do :; done' & busy_pids+=($!)
done

export OMP_NUM_THREADS="$threads"
results="$work/results.tsv"
printf "tool\trun\twall_s\tms_per_it\tcpu_s\tpeak_mb\tpsnr\tload\n" > "$results"
# Prints and keeps the row of run $2 of tool $1: its time -v log $3, its
# held-out PSNR $4 and the load average at its start $5.
add_row() {
  local w; w=$(wall_s "$3")
  printf "%s\t%d\t%s\t%.1f\t%s\t%s\t%s\t%s\n" "$1" "$2" "$w" \
      "$(echo "$w * 1000 / $iterations" | bc -l)" "$(cpu_s "$3")" "$(peak_mb "$3")" \
      "$4" "$5" | tee -a "$results"
}
for ((r = 1; r <= runs; ++r)); do
  out="$work/es_static_$r"; log="$work/es_static_$r.time"; l=$(load)
  /usr/bin/time -v -o "$log" "$es_static" --scene "$scene" --out "$out" \
      --iterations "$iterations" --sh_degree "$sh_degree" \
      --sh_degree_interval 1000 --densify=false --mask_weight 0 \
      --checkpoint_every 0 --log_every 0 > "$out.log" 2>&1 \
      || { tail -5 "$out.log"; exit 1; }
  # es_static's own time excludes loading; /usr/bin/time's includes it.
  psnr=$(sed -n 's/.*"psnr_test": *\([-0-9.naif]*\).*/\1/p' "$out/metrics.json" | head -1)
  add_row es_static "$r" "$log" "$psnr" "$l"
  [[ -n "$opensplat" ]] || continue
  out="$work/opensplat_$r"; log="$out.time"; l=$(load); mkdir -p "$out"
  /usr/bin/time -v -o "$log" "$opensplat" "$os_scene" --cpu \
      -n "$iterations" --sh-degree "$sh_degree" --sh-degree-interval 1000 \
      --densify-from $((iterations + 1)) --refine-every $((iterations + 1)) \
      --val --val-image "$held_out" -o "$out/splat.ply" > "$out.log" 2>&1 \
      || { tail -5 "$out.log"; exit 1; }
  psnr=$(sed -n 's/.*validation PSNR: *\([-0-9.naif]*\).*/\1/p' "$out.log" | tail -1)
  add_row opensplat "$r" "$log" "$psnr" "$l"
done
[[ -n "$opensplat" ]] || echo "[bench] no OpenSplat binary: es_static only (pass --opensplat_src DIR to build one)"
echo "medians (wall s, ms/iteration, CPU s, peak MB, PSNR):"
for tool in es_static opensplat; do
  awk -F'\t' -v t="$tool" '$1 == t' "$results" | sort -t$'\t' -k3,3n |
    awk -F'\t' '{a[NR] = $0} END {if (NR) {split(a[int((NR + 1) / 2)], f, "\t");
      printf "  %-10s %s s  %s ms  %s CPU s  %s MB  %s dB (%d runs)\n", f[1], f[3], f[4], f[5], f[6], f[7], NR}}'
done
