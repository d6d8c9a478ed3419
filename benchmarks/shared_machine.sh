#!/usr/bin/env bash
# A trainer on a shared machine (docs/BENCHMARKS.md, "A shared machine"):
# es_train with N threads, alone and beside one busy process (a shell
# loop that never sleeps), each with the apps' own OpenMP wait policy (a
# short spin, then sleep: GOMP_SPINCOUNT=10000, set by the apps when the
# user sets none) and with libgomp's default (GOMP_SPINCOUNT=300000, its
# spin count when OMP_WAIT_POLICY is unset). Prints wall and CPU seconds
# (user + system, /usr/bin/time) of every run; the load average at each
# start says what else the machine was doing. Not part of the tests.
#
#   benchmarks/shared_machine.sh [options]
#     --work DIR        scratch folder (default /tmp/es_shared_machine)
#     --threads N       es_train's --threads (default 2)
#     --iterations N    es_train iterations per run (default 100)
#     --runs N          runs of each setting, interleaved (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/options.sh
work=/tmp/es_shared_machine; threads=2; iterations=100; runs=2
parse_options "work threads iterations runs" "" "$@"
bin=build/bin
require_apps es_synth es_static es_train
mkdir -p "$work"
scene="$work/scene" init="$work/static"
if [[ ! -f "$scene/sparse/0/images.txt" ]]; then
  echo "[shared] es_synth -> $scene (the README's scene)"
  "$bin/es_synth" --out "$scene" --preset waterfall --frames 60 \
      --width 160 --height 120 --detail 0.3 --num_points 2000 \
      > "$work/synth.log"
fi
if [[ ! -f "$init/static.ply" ]]; then
  echo "[shared] es_static 300 iterations -> $init"
  "$bin/es_static" --scene "$scene" --out "$init" --iterations 300 \
      --eval_every 0 --checkpoint_every 0 > "$work/static.log"
fi

busy_pid=""
stop_busy() { [[ -z "$busy_pid" ]] || kill "$busy_pid" 2>/dev/null || true
              busy_pid=""; }
trap stop_busy EXIT

# run POLICY COMPETITOR: one es_train run; prints its line.
run() {
  local policy=$1 competitor=$2 env_policy=()
  [[ $policy == libgomp ]] && env_policy=(GOMP_SPINCOUNT=300000)
  if [[ $competitor == busy ]]; then
    bash -c 'while :; do :; done' & busy_pid=$!
  fi
  local load out="$work/train_${policy}_${competitor}"
  load=$(cut -d' ' -f1 /proc/loadavg)
  rm -rf "$out"
  env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u OMP_NUM_THREADS \
      -u ES_WAIT_POLICY_APPLIED "${env_policy[@]}" \
      /usr/bin/time -f "%e %U %S" -o "$work/time.txt" \
      "$bin/es_train" --scene "$scene" --init "$init" --out "$out" \
      --iterations "$iterations" --threads "$threads" --checkpoint_interval 0 \
      --eval_interval 0 --log_interval 0 --seed 0 > "$work/train.log" 2>&1 \
    || { stop_busy; tail -20 "$work/train.log"; exit 1; }
  stop_busy
  read -r wall user sys < "$work/time.txt"
  printf "%-8s %-6s %6s %8.1f %8.1f %6.2f\n" "$policy" "$competitor" "$load" \
    "$wall" "$(echo "$user + $sys" | bc -l)" \
    "$(echo "($user + $sys) / $wall" | bc -l)"
}

echo "[shared] es_train, $iterations iterations, --threads $threads," \
     "$(nproc) cores, $runs run(s) of each"
printf "%-8s %-6s %6s %8s %8s %6s\n" policy other load wall_s cpu_s cores
for ((r = 0; r < runs; ++r)); do
  for competitor in none busy; do
    for policy in app libgomp; do run "$policy" "$competitor"; done
  done
done
echo "policy app: the apps' short spin (GOMP_SPINCOUNT=10000);" \
     "libgomp: GOMP_SPINCOUNT=300000; other busy: one shell loop beside it"
