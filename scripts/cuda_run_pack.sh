#!/usr/bin/env bash
# Runs the CUDA checks on a GPU machine from the archive that
# scripts/cuda_pack.sh made elsewhere (.cuda_pack/pack.tar.xz): prints the
# GPU, runs every test (four programs at a time, each under a time limit;
# none may skip), the benchmarks, the paper preset shortened (fewer frames
# and iterations, each stage timed), then compute-sanitizer's memcheck of
# the tests while the time allows. The summary goes to stdout and,
# with every log, to $OUT (summary.txt, logs.tar.gz) when that is set.
#
#   scripts/cuda_run_pack.sh [SECONDS]   stop starting new work after
#                                        SECONDS (default 420)
#
# Environment: ES_TESTS / ES_BENCHES (space-separated) run only those
# (memcheck covers every test); ES_TEST_ARGS go to each test program;
# ES_BENCH_MIN_TIME (default 0.3) is each benchmark's minimum seconds;
# ES_E2E_FRAMES (default 60) and ES_E2E_ITERATIONS (static, flow and joint
# iterations; default "1000 200 1000") size the shortened paper preset.
# Exit status: 0 when every test ran and passed.
set -uo pipefail
source "$(dirname "$0")/lib/options.sh"
help_if_asked "$@"
cd "$(dirname "$0")/.."
budget=${1:-420}
pack=.cuda_pack/pack.tar.xz
[[ -f "$pack" ]] || {
  echo "cuda_run_pack.sh: $pack missing (run scripts/cuda_pack.sh where" \
       "nvcc is, and bring .cuda_pack along)" >&2; exit 1; }
root=/tmp/es_pack
logs=/tmp/es_pack_logs
rm -rf "$root" "$logs"; mkdir -p "$root" "$logs"
tar -C "$root" -xJf "$pack"
export LD_LIBRARY_PATH="$root/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PATH="$PATH:/usr/local/cuda/bin"
summary=$logs/summary.txt
note() { echo "$*" | tee -a "$summary"; }
finish() {
  if [[ -n "${OUT:-}" ]]; then
    cp "$summary" "$OUT/"
    tar -C "$logs" -czf "$OUT/logs.tar.gz" .
  fi
}
trap finish EXIT

note "== cuda_run_pack at $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
note "GPU: $(nvidia-smi --format=csv,noheader \
  --query-gpu=name,compute_cap,driver_version,memory.total 2>&1)"

# Tests, four programs at a time; ES_CUDA_SYNC=1 makes a kernel's fault
# name that kernel.
note "== tests"
tests=${ES_TESTS:-$(cat "$root/tests.txt")}
export ES_CUDA_SYNC=1 OMP_NUM_THREADS=4 root logs ES_TEST_ARGS
printf '%s\n' $tests | xargs -P4 -I{} bash -c \
  'timeout 300 "$root/bin/{}" --gtest_color=no $ES_TEST_ARGS \
     > "$logs/{}.txt" 2>&1; echo "{} $?" >> "$logs/status.txt"'
unset ES_CUDA_SYNC OMP_NUM_THREADS
status=0
for t in $tests; do
  log=$logs/$t.txt
  rc=$(awk -v t="$t" '$1 == t { print $2 }' "$logs/status.txt")
  passed=$(grep -o '\[  PASSED  \] [0-9]*' "$log" | grep -o '[0-9]*$')
  skipped=$(grep -c '^\[  SKIPPED \] [A-Za-z]' "$log")
  note "$t: exit $rc, ${passed:-0} passed, $skipped skipped$(
    ((rc == 124)) && echo ', OUT OF TIME')"
  grep -E '^\[  FAILED  \] [A-Za-z]' "$log" | sed 's/^/    /' | tee -a "$summary"
  if [[ "$rc" != 0 || "$skipped" != 0 ]]; then status=1; fi
done
# The first failures' messages.
grep -h -E -A6 ': Failure$|CudaError|what\(\)|Check failed' "$logs"/*_test.txt |
  head -120 | tee -a "$summary"
note "tests done at $SECONDS s"

note "== benchmarks"
for b in ${ES_BENCHES:-$(cat "$root/benches.txt")}; do
  ((SECONDS < budget)) || { note "$b: not run (past $budget s)"; continue; }
  timeout 240 "$root/bin/$b" --benchmark_counters_tabular=true \
    --benchmark_min_time="${ES_BENCH_MIN_TIME:-0.3}" > "$logs/$b.txt" 2>&1
  note "$b: exit $? at $SECONDS s"
  grep -v -E '^\*\*\*|^-+$' "$logs/$b.txt" | tee -a "$summary"
done

# The paper preset at its resolution with fewer frames and iterations: each
# stage's wall time, to scale to the full preset's iteration counts, and
# es_train's time per part of an iteration (--profile).
read -r e2e_static e2e_flow e2e_joint <<< "${ES_E2E_ITERATIONS:-1000 200 1000}"
e2e_frames=${ES_E2E_FRAMES:-60}
if ((SECONDS + 150 < budget)); then
  note "== paper preset, shortened: 1168x880, $e2e_frames frames," \
       "$e2e_static static / $e2e_flow flow / $e2e_joint joint iterations"
  "$root/bin/es_synth" --out /tmp/es_e2e_scene --preset waterfall \
    --frames "$e2e_frames" --width 1168 --height 880 > "$logs/e2e.txt" 2>&1
  timer=(); [[ -x /usr/bin/time ]] && timer=(/usr/bin/time -v)
  timeout $((budget - SECONDS + 60)) "${timer[@]}" "$root/bin/eulersplat" \
    --scene /tmp/es_e2e_scene --out /tmp/es_e2e --preset paper --device cuda \
    --static_iterations "$e2e_static" --flow_iterations "$e2e_flow" \
    --joint_iterations "$e2e_joint" --animate=false \
    --train_flags=--profile >> "$logs/e2e.txt" 2>&1
  note "eulersplat exit $? at $SECONDS s"
  grep -E 'so far|done in|it/s|Elapsed|Maximum resident|PSNR|EPE|rror' \
    "$logs/e2e.txt" | tail -40 | tee -a "$summary"
  sed -n '/^profile:/,/^total /p' "$logs/e2e.txt" | tee -a "$summary"
fi

# Memcheck, four programs at a time, while the time allows.
if command -v compute-sanitizer > /dev/null && ((SECONDS + 60 < budget)); then
  note "== compute-sanitizer memcheck (until $budget s)"
  export memcheck_limit=$((budget - SECONDS))
  # Asks for more memory than the GPU has, on purpose: memcheck reports
  # that failed call as an error.
  export deliberate=CudaErrorTest.FailedCallsThrowWithPlaceAndCause
  xargs -P4 -I{} bash -c \
    'timeout "$memcheck_limit" compute-sanitizer --tool memcheck \
       --error-exitcode 3 "$root/bin/{}" --gtest_filter=-$deliberate \
       > "$logs/memcheck_{}.txt" 2>&1;
     echo "{} $?" >> "$logs/memcheck_status.txt"' < "$root/tests.txt"
  while read -r t rc; do
    note "memcheck $t: exit $rc (0 clean, 3 errors, 124 out of time)"
    grep -m5 -E 'Invalid|out of bounds|ERROR SUMMARY: [1-9]' \
      "$logs/memcheck_$t.txt" | sed 's/^/    /' | tee -a "$summary"
  done < <(sort "$logs/memcheck_status.txt")
fi
note "== done in $SECONDS s; tests $([[ $status == 0 ]] && echo passed || echo FAILED)"
exit "$status"
