#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UBSan) into
# build-asan/ and runs each for SECONDS seconds, one at a time, from seed
# corpora the project's own writers make. Any crash, hang (> 10 s on one
# input), undefined behaviour or single allocation over 512 MB stops that
# target and leaves its input in build-asan/artifacts/.
#   scripts/fuzz.sh [SECONDS=60] [TARGET...]   (default: every target)
# Prints executions per target; the corpora grow in build-asan/corpus/.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--help" || "${1:-}" == "-h" ]]; then
  sed -n '2,8p' "$0"; exit 0
fi
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(fuzz_ply fuzz_colmap_text fuzz_colmap_binary
                               fuzz_split fuzz_field fuzz_checkpoint)
jobs=${JOBS:-2}
source scripts/lib/asan_build.sh
configure_asan_build
echo "[fuzz] building ${targets[*]} (log: $build.log)"
cmake --build "$build" -j"$jobs" --target make_fuzz_seeds "${targets[@]}" \
  >> "$build.log" 2>&1 || { tail -40 "$build.log"; exit 1; }
rm -rf "$build/seeds"
"$build/bin/make_fuzz_seeds" "$build/seeds"
mkdir -p "$build/artifacts"
status=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t"
  mkdir -p "$corpus"
  cp -n "$build/seeds/$t"/* "$corpus"/
  log="$build/$t.log"
  set +e
  "$build/bin/$t" "$corpus" -dict="tests/fuzz/$t.dict" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=512 -max_len=4096 -print_final_stats=1 \
    -artifact_prefix="$build/artifacts/$t-" > "$log" 2>&1
  rc=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" |
         grep -o '[0-9]*$' || echo "?")
  if ((rc == 0)); then
    echo "[fuzz] $t: $runs executions in ${seconds} s, no findings"
  else
    echo "[fuzz] $t: FINDING after $runs executions (exit $rc); see $log"
    grep -m3 -E "ERROR|runtime error|SUMMARY" "$log" || true
    status=1
  fi
done
exit $status
