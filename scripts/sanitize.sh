#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer
# (clang, -DES_SANITIZE=address,undefined) into build-asan/ and runs the
# whole test suite under it. Any report fails the test it occurs in.
#   scripts/sanitize.sh [ctest -R regex]
# Shares build-asan/ with scripts/fuzz.sh. Slow: a full instrumented build,
# then tests that run several times slower than in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--help" || "${1:-}" == "-h" ]]; then
  sed -n '2,7p' "$0"; exit 0
fi
jobs=${JOBS:-2}
source scripts/lib/asan_build.sh
configure_asan_build
echo "[sanitize] building (log: $build.log)"
start=$(date +%s)
cmake --build "$build" -j"$jobs" >> "$build.log" 2>&1 ||
  { grep -E -B2 -A6 "error" "$build.log" | head -60; exit 1; }
echo "[sanitize] built in $(( $(date +%s) - start )) s; running the suite"
start=$(date +%s)
# halt_on_error: the first report fails the test; detect_leaks stays on.
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
regex=()
[[ -n "${1:-}" ]] && regex=(-R "$1")
status=0
(cd "$build" && ctest -j"$jobs" --timeout 1500 --output-on-failure \
   "${regex[@]}") || status=$?
echo "[sanitize] suite ran in $(( $(date +%s) - start )) s (exit $status)"
exit $status
