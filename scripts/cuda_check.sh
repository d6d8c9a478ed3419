#!/usr/bin/env bash
# The CUDA backend's check, the one command a session with an NVIDIA GPU
# runs: builds only the CUDA rasterizer, losses, Adam, fields (V, D),
# Euler chain, frame composer and loop renderer, their tests and the
# benchmarks
# (-DES_CUDA=ON -DES_CUDA_CHECK_ONLY=ON: no Ceres or OpenCV needed),
# prints the GPU, runs the tests, once more under compute-sanitizer's
# memcheck (and some under racecheck) when it is installed and time
# allows, then the benchmarks; then, where Ceres and OpenCV are
# installed, a full -DES_CUDA=ON build of the device Stage 1 trainer's
# test and benchmark, the Stage 3 trainer's, the Stage 3 losses' tests
# (joint render cost, water energy, flow prior) and es_eval's device
# rendering test, run too. Copies the logs to $OUT when that is set.
# Under 8 minutes on 16 cores for the first step (the full build adds
# minutes of its own); the summary at the
# end holds what a reader needs.
#
#   scripts/cuda_check.sh           build and run the checks (GPU machine)
#   scripts/cuda_check.sh --bundle  save the Debian packages the build
#                                   needs into .cuda_deps/ (run where the
#                                   package mirror is reachable; carry the
#                                   folder to a GPU machine without it)
#
# Dependencies: Eigen, glog, GoogleTest and Google Benchmark from the
# system when installed, else unpacked from .cuda_deps/ into /tmp/es_deps
# (the packages' files only, nothing installed). ES_JOBS sets the build's
# parallel jobs (default 16). Exit status: 0 when the build and every test
# pass.
set -uo pipefail
cd "$(dirname "$0")/.."

DEPS=(libeigen3-dev libgoogle-glog-dev libgoogle-glog0v6 libgflags-dev
      libgflags2.2 libunwind-dev libunwind8 libgtest-dev libbenchmark-dev
      libbenchmark1debian)

case "${1:-}" in
  -h|--help)
    awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
    exit 0 ;;
  --bundle)
    mkdir -p .cuda_deps
    (cd .cuda_deps && apt-get download "${DEPS[@]}") || exit 1
    du -sh .cuda_deps; exit 0 ;;
  "") ;;
  *) echo "cuda_check.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
esac

start=$SECONDS
logs=/tmp/es_cuda_check
rm -rf "$logs"; mkdir -p "$logs"
build=build_cuda_check
summary="$logs/summary.txt"
: > "$summary"
note() { echo "$*" | tee -a "$summary"; }
# Copies the logs to $OUT (when set) on every exit.
finish() {
  if [[ -n "${OUT:-}" ]]; then cp "$logs"/*.txt "$OUT"/ 2>/dev/null; fi
}
trap finish EXIT

note "== cuda_check at $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
if command -v nvidia-smi > /dev/null; then
  note "GPU: $(nvidia-smi --format=csv,noheader \
    --query-gpu=name,compute_cap,driver_version,memory.total 2>&1)"
else
  note "GPU: nvidia-smi not found"
fi
export PATH="$PATH:/usr/local/cuda/bin"
note "nvcc: $(nvcc --version 2>/dev/null | tail -1 || echo 'not found')"
arch=$(nvidia-smi --query-gpu=compute_cap --format=csv,noheader 2>/dev/null |
       head -1 | tr -d '. ')
[[ "$arch" =~ ^[0-9]+$ ]] || arch=90

# Dependencies.
cmake_args=()
missing=()
for p in "${DEPS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null |
    grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if compgen -G ".cuda_deps/*.deb" > /dev/null; then
    note "deps: unpacking .cuda_deps/ into /tmp/es_deps" \
         "(missing: ${missing[*]})"
    rm -rf /tmp/es_deps; mkdir -p /tmp/es_deps
    for f in .cuda_deps/*.deb; do
      if command -v dpkg > /dev/null; then
        dpkg -x "$f" /tmp/es_deps
      else  # a .deb is an ar archive around data.tar.*
        ar p "$f" "$(ar t "$f" | grep '^data\.tar')" > /tmp/es_deps/data.tar
        tar -xf /tmp/es_deps/data.tar -C /tmp/es_deps
        rm /tmp/es_deps/data.tar
      fi
    done
    cmake_args+=(-DCMAKE_PREFIX_PATH=/tmp/es_deps/usr
                 -DCMAKE_MODULE_PATH=/tmp/es_deps/usr/share/glog/cmake)
    lib=/tmp/es_deps/usr/lib/x86_64-linux-gnu
    export LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  else
    note "deps: missing ${missing[*]} and no .cuda_deps/ (run --bundle" \
         "where the mirror is reachable, carry .cuda_deps); trying anyway"
  fi
else
  note "deps: from the system"
fi
# CMake 4 refuses package files that ask for policies older than 3.5.
cmake_args+=(-DCMAKE_POLICY_VERSION_MINIMUM=3.5)
command -v ninja > /dev/null && cmake_args+=(-G Ninja)
command -v ccache > /dev/null &&
  cmake_args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache
               -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)

# Build.
note "== build (sm_$arch)"
if ! cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DES_CUDA=ON \
       -DES_CUDA_CHECK_ONLY=ON -DCMAKE_CUDA_ARCHITECTURES="$arch" \
       "${cmake_args[@]}" > "$logs/build.txt" 2>&1 ||
   ! cmake --build "$build" -j"${ES_JOBS:-16}" --target cuda_rasterizer_test \
       cuda_photometric_loss_test cuda_mask_bce_loss_test \
       cuda_residual_l2_loss_test cuda_adam_test cuda_fields_test \
       cuda_residual_field_test cuda_euler_chain_test \
       cuda_loop_animator_test cuda_loop_renderer_test cuda_loop_frames_test \
       cuda_frame_composer_test bench_cuda_rasterizer \
       bench_cuda_loop \
       >> "$logs/build.txt" 2>&1; then
  grep -E -B2 -A8 "error|Error|CMake Error" "$logs/build.txt" | head -80
  note "BUILD FAILED after $((SECONDS - start)) s (log: build.txt)"
  exit 1
fi
note "built in $((SECONDS - start)) s"

# Tests.
note "== tests"
# ES_CUDA_SYNC=1: a fault inside a kernel names that kernel.
(cd "$build" && ES_CUDA_SYNC=1 ctest --output-on-failure --timeout 300 -j4) \
  > "$logs/tests.txt" 2>&1
tests_status=$?
grep -E "tests passed|tests failed|Total Test time" "$logs/tests.txt" |
  tee -a "$summary"
if ((tests_status != 0)); then
  note "failed tests:"
  sed -n '/The following tests FAILED/,$p' "$logs/tests.txt" | tee -a "$summary"
  # The first failures' messages, for the summary the caller sees.
  grep -E -A5 ": Failure$|CudaError|what\(\)" "$logs/tests.txt" |
    head -80 | tee -a "$summary"
fi

skipped=$(grep -c "(Skipped)" "$logs/tests.txt")
if ((skipped > 0)); then
  # ctest counts a skip as a pass; on a GPU machine none may skip.
  note "$skipped tests SKIPPED: $(grep -m1 -o 'no usable CUDA device.*' \
    "$build/Testing/Temporary/LastTest.log" 2>/dev/null)"
  tests_status=1
fi

# Memory and shared-memory race checks, while the time allows (each run
# takes minutes).
if command -v compute-sanitizer > /dev/null && ((SECONDS - start < 240)); then
  note "== compute-sanitizer memcheck"
  timeout 150 compute-sanitizer --tool memcheck --error-exitcode 3 \
    "$build/bin/cuda_rasterizer_test" --gtest_filter='-*Dense*' \
    > "$logs/memcheck.txt" 2>&1
  note "memcheck exit status $? (0 clean, 3 errors, 124 out of time)"
  # The loss, Adam, field and Euler-chain tests are short: all of them.
  for t in cuda_photometric_loss_test cuda_mask_bce_loss_test \
           cuda_residual_l2_loss_test cuda_adam_test cuda_fields_test \
           cuda_residual_field_test cuda_euler_chain_test \
           cuda_loop_animator_test cuda_loop_renderer_test \
           cuda_loop_frames_test cuda_frame_composer_test; do
    timeout 60 compute-sanitizer --tool memcheck --error-exitcode 3 \
      "$build/bin/$t" >> "$logs/memcheck.txt" 2>&1
    note "memcheck of $t exit status $?"
  done
  grep -E "ERROR SUMMARY|Invalid|out of bounds" "$logs/memcheck.txt" |
    head -20 | tee -a "$summary"
  if ((SECONDS - start < 330)); then
    note "== compute-sanitizer racecheck"
    timeout 90 compute-sanitizer --tool racecheck --error-exitcode 3 \
      "$build/bin/cuda_rasterizer_test" \
      --gtest_filter='*Needles*:*OpaqueStack*/3:*TilesList*' \
      > "$logs/racecheck.txt" 2>&1
    note "racecheck exit status $? (0 clean, 3 errors, 124 out of time)"
    # The MLP's tiled products share their tiles through shared memory.
    timeout 60 compute-sanitizer --tool racecheck --error-exitcode 3 \
      "$build/bin/cuda_fields_test" --gtest_filter='*DeviceMlpTest*' \
      >> "$logs/racecheck.txt" 2>&1
    note "racecheck of the MLP exit status $?"
    grep -E "ERROR SUMMARY|RACECHECK SUMMARY|hazard" "$logs/racecheck.txt" |
      head -20 | tee -a "$summary"
  fi
else
  note "sanitizers skipped (no compute-sanitizer, or past 240 s)"
fi

# Benchmarks.
note "== benchmarks"
timeout 200 "$build/bin/bench_cuda_rasterizer" \
  --benchmark_counters_tabular=true > "$logs/bench.txt" 2>&1
note "bench exit status $?"
tee -a "$summary" < "$logs/bench.txt"
timeout 150 "$build/bin/bench_cuda_loop" \
  --benchmark_counters_tabular=true > "$logs/bench_loop.txt" 2>&1
note "bench_cuda_loop exit status $?"
tee -a "$summary" < "$logs/bench_loop.txt"

# Second step: what needs Ceres and OpenCV (the device trainers of Stages
# 1 and 3, the device joint render cost, es_eval's device rendering, the
# --device flag, their tests and benchmarks) is not in the check-only
# build above; where those are installed, a full build with -DES_CUDA=ON
# builds and runs them (otherwise this says so and skips; the verdict then
# covers the first step only).
full=build_cuda_full
full_deps=(libceres-dev libopencv-dev nlohmann-json3-dev)
full_tests=(cuda_static_trainer_test cuda_joint_render_cost_test
            cuda_water_energy_loss_test cuda_flow_prior_test
            cuda_flow_pretrain_test cuda_joint_trainer_test
            cuda_eval_rendering_test device_flag_test)
full_benches=(bench_cuda_static bench_cuda_joint)
if dpkg-query -W -f='${Status}\n' "${full_deps[@]}" 2>/dev/null |
     grep -c "install ok installed" | grep -qx "${#full_deps[@]}"; then
  note "== full build: device trainers (sm_$arch)"
  if cmake -S . -B "$full" -DCMAKE_BUILD_TYPE=Release -DES_CUDA=ON \
         -DCMAKE_CUDA_ARCHITECTURES="$arch" "${cmake_args[@]}" \
         > "$logs/build_full.txt" 2>&1 &&
     cmake --build "$full" -j"${ES_JOBS:-16}" --target \
         "${full_tests[@]}" "${full_benches[@]}" \
         >> "$logs/build_full.txt" 2>&1; then
    : > "$logs/trainer_tests.txt"
    trainer_status=0
    for t in "${full_tests[@]}"; do
      ES_CUDA_SYNC=1 timeout 300 "$full/bin/$t" \
        >> "$logs/trainer_tests.txt" 2>&1 || trainer_status=1
    done
    grep -E "PASSED|FAILED|SKIPPED|Failure" -A3 "$logs/trainer_tests.txt" |
      head -60 | tee -a "$summary"
    ((trainer_status == 0)) || tests_status=1
    grep -q "SKIPPED" "$logs/trainer_tests.txt" && tests_status=1
    for b in "${full_benches[@]}"; do
      timeout 200 "$full/bin/$b" \
        --benchmark_counters_tabular=true > "$logs/$b.txt" 2>&1
      note "$b exit status $?"
      tee -a "$summary" < "$logs/$b.txt"
    done
  else
    grep -E -B2 -A8 "error|Error" "$logs/build_full.txt" | head -60 |
      tee -a "$summary"
    note "FULL BUILD FAILED (log: build_full.txt)"
    tests_status=1
  fi
else
  note "full build skipped: not all of ${full_deps[*]} installed" \
       "(the device trainers' tests and benchmarks need them)"
fi

verdict=$([[ $tests_status == 0 ]] && echo passed || echo FAILED)
note "== done in $((SECONDS - start)) s; tests $verdict"
exit "$tests_status"
