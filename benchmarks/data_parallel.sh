#!/usr/bin/env bash
# Measures data-parallel training over MPI ranks (docs/BENCHMARKS.md,
# "Data-parallel training") on a 320x240, 120-frame es_synth waterfall:
#   1. es_static, one thread per process, batches of 2 frames: in one
#      process, and on 2 ranks (mpiexec -n 2), --profile's ms per
#      iteration and the allreduce's share of rank 0's iteration;
#   2. the same for es_train from the first run's model;
#   3. a model of the speed-up at 8 ranks (one frame each) from the
#      measured per-frame compute, the fixed per-iteration work (Adam) and
#      the allreduce's size: on this machine's loopback, as measured, and
#      on 10 Gbit/s Ethernet between machines (a ring allreduce moves
#      2 (p-1)/p of the buffer per rank). The 2-rank runs send only the
#      chunks some rank holds non-zero (their MB); 8 frames touch more of
#      the fields, so the model takes the whole buffer (the one-process
#      runs' MB), an upper bound.
# Each line carries the load average at its start (above ~0.5: not an
# idle figure). Needs a build with MPI (-DES_MPI) and mpiexec on PATH.
#
#   benchmarks/data_parallel.sh [options]
#     --work DIR       scratch folder (default /tmp/es_data_parallel)
#     --static_its N   es_static iterations per run (300)
#     --joint_its N    es_train iterations per run (100)
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; }
work=/tmp/es_data_parallel ; static_its=300 ; joint_its=100
while (($#)); do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --static_its) static_its="$2"; shift 2 ;;
    --joint_its) joint_its="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for n in "$static_its" "$joint_its"; do
  [[ "$n" =~ ^[0-9]+$ && "$n" -gt 0 ]] || { echo "not a positive number: '$n'" >&2; exit 2; }
done
bin=build/bin
for b in es_synth es_static es_train; do
  [[ -x "$bin/$b" ]] || { echo "$bin/$b missing: run scripts/setup.sh" >&2; exit 1; }
done
command -v mpiexec > /dev/null ||
  { echo "mpiexec missing (apt-get install openmpi-bin)" >&2; exit 1; }
mpi=(mpiexec -n 2 -x OMP_NUM_THREADS=1)
[[ $(id -u) -eq 0 ]] && mpi+=(--allow-run-as-root)
mkdir -p "$work"
load() { cut -d' ' -f1 /proc/loadavg; }
# A row of a --profile table: its ms per iteration ($3) or share ($4).
row() { awk -v name="$2" -v col="$3" '
  index($0, name) == 1 && !found { sub(/%$/, "", $NF); print (col == "ms" ? $(NF-1) : $NF); found = 1 }
  END { if (!found) print 0 }' "$1"; }
mb() { sed -n 's/.*allreduce \([0-9.]*\) MB per iteration.*/\1/p' "$1"; }

echo "[ranks] $(date -u +%FT%TZ), $(nproc) CPUs, commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
scene="$work/scene320"
if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
  echo "[ranks] es_synth -> $scene (320x240, 120 frames)"
  "$bin/es_synth" --out "$scene" --preset waterfall --frames 120 \
      --width 320 --height 240 > "$work/synth.log"
fi

common_static=(--scene "$scene" --iterations "$static_its" --densify=false
               --checkpoint_every 0 --eval_every 0 --log_every 0 --profile
               --batch_frames 2)
common_joint=(--scene "$scene" --init "$work/static_1" --iterations "$joint_its"
              --no_flow_init --checkpoint_interval 0 --eval_interval 0
              --log_interval 0 --profile --densify_water_interval 0
              --batch_frames 2)
declare -A log
for stage in static joint; do
  for ranks in 1 2; do
    out="$work/${stage}_$ranks"
    log[$stage$ranks]="$out.log"
    if [[ $stage == static ]]; then cmd=("$bin/es_static" "${common_static[@]}" --out "$out")
    else cmd=("$bin/es_train" "${common_joint[@]}" --out "$out"); fi
    l=$(load)
    if ((ranks == 1)); then OMP_NUM_THREADS=1 "${cmd[@]}" > "$out.log" 2>&1
    else "${mpi[@]}" "${cmd[@]}" > "$out.log" 2>&1; fi ||
      { tail -5 "$out.log"; exit 1; }
    printf '  %-6s %d rank(s): %8.2f ms/iteration, allreduce %6.2f ms (%4.1f%%), waiting for ranks %6.2f ms, %s MB (load %s)\n' \
      "$stage" "$ranks" "$(row "$out.log" total ms)" "$(row "$out.log" allreduce ms)" \
      "$(row "$out.log" allreduce share)" "$(row "$out.log" "waiting for ranks" ms)" \
      "$(mb "$out.log")" "$l"
  done
done

echo "[ranks] model: 8 ranks, one frame each, against one process on the same 8 frames"
for stage in static joint; do
  python3 - "$stage" "$(row "${log[${stage}1]}" total ms)" "$(row "${log[${stage}1]}" Adam ms)" \
      "$(row "${log[${stage}2]}" allreduce ms)" "$(mb "${log[${stage}2]}")" \
      "$(mb "${log[${stage}1]}")" <<'PY'
import sys
stage, total, adam, reduce_ms, sent, mbytes = sys.argv[1], *map(float, sys.argv[2:])
frame = (total - adam) / 2            # one frame's render, loss and backward
loopback = sent / max(reduce_ms, 1e-9)  # MB per ms moved at p = 2 (ring: 1x the buffer)
for name, mb_per_ms in (("loopback as measured", loopback), ("10 Gbit/s Ethernet", 1.25)):
    p = 8
    ring = 2 * (p - 1) / p * mbytes / mb_per_ms
    one, ranks = p * frame + adam, frame + adam + ring
    print(f"  {stage:6s} {name:21s}: frame {frame:.1f} ms, Adam {adam:.1f} ms, "
          f"allreduce {ring:.1f} ms of {mbytes:.1f} MB -> "
          f"{one:.0f} vs {ranks:.0f} ms per iteration, speed-up {one / ranks:.1f}x")
PY
done
