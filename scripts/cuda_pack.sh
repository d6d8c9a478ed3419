#!/usr/bin/env bash
# Builds the CUDA backend's tests and benchmarks here, where nvcc is but no
# GPU need be, and packs them with the shared libraries they load into one
# archive that a GPU machine with neither compilers nor packages can run
# (scripts/cuda_run_pack.sh there). The GPU's minutes then go to the checks,
# not to the build. The full build (-DES_CUDA=ON, with Ceres and OpenCV):
# the kernels' tests and the device trainers', every CUDA benchmark, and
# the driver and its stages (es_synth to make a scene) for timed runs.
#
#   scripts/cuda_pack.sh [ARCH]    build for sm_ARCH (default 90: H100,
#                                  H200) into build_gpu/ and write
#                                  .cuda_pack/pack.tar.xz
#
# The archive holds bin/ (the programs), lib/ (every library they load but
# the C library, the C++ runtime and the CUDA driver, which the GPU machine
# has; OpenCV's unused readers as stubs: scripts/cuda_pack_libs.py) and
# tests.txt / benches.txt (what cuda_run_pack.sh runs). ES_JOBS
# sets the build's parallel jobs (default: the cores).
set -euo pipefail
source "$(dirname "$0")/lib/options.sh"
help_if_asked "$@"
cd "$(dirname "$0")/.."
arch=${1:-90}
[[ "$arch" =~ ^[0-9]+$ ]] || {
  echo "cuda_pack.sh: ARCH must be a number like 90, not '$arch'" >&2; exit 2; }
nvcc=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
[[ -x "$nvcc" ]] || { echo "cuda_pack.sh: nvcc not found" >&2; exit 1; }

build=build_gpu
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DES_CUDA=ON \
  -DCMAKE_CUDA_COMPILER="$nvcc" -DCMAKE_CUDA_ARCHITECTURES="$arch" > /dev/null
tests=$(cd tests/cuda && ls *_test.cc | sed 's/\.cc$//'; echo device_flag_test)
benches=$(cd apps/cuda && ls bench_*.cc | sed 's/\.cc$//')
apps="es_synth es_poses es_static es_flowinit es_train es_animate es_eval
      es_export es_plot eulersplat"
# shellcheck disable=SC2086
cmake --build "$build" -j"${ES_JOBS:-$(nproc)}" --target $tests $benches $apps

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib"
for b in $tests $benches $apps; do cp "$build/bin/$b" "$stage/bin/"; done
echo "$tests" > "$stage/tests.txt"
echo "$benches" > "$stage/benches.txt"
python3 scripts/cuda_pack_libs.py "$stage/bin" "$stage/lib"
# One stream with a dictionary that spans the programs, which share most
# of their code.
mkdir -p .cuda_pack
tar -C "$stage" -cf - . | xz -9 --lzma2=preset=9,dict=256MiB \
  > .cuda_pack/pack.tar.xz
echo "cuda_pack.sh: .cuda_pack/pack.tar.xz ($(du -h .cuda_pack/pack.tar.xz |
  cut -f1); $(ls "$stage/bin" | wc -l) programs, $(ls "$stage/lib" |
  wc -l) libraries), built for sm_$arch at $(git rev-parse --short HEAD)"
