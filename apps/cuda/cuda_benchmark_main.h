#ifndef EULERSPLAT_APPS_CUDA_CUDA_BENCHMARK_MAIN_H_
#define EULERSPLAT_APPS_CUDA_CUDA_BENCHMARK_MAIN_H_

#include <cstdio>
#include <string>

#include "apps/common/benchmark_main.h"
#include "core/base/cuda/cuda_error.h"

namespace es {
namespace cuda {

// main() of a CUDA benchmark binary (`name` in its messages): without a
// CUDA device it says why and exits 0, so a build machine without a GPU
// can run it; else it names the device and runs the benchmarks.
inline int RunCudaBenchmarks(const char* name, int argc, char** argv) {
  std::string why;
  if (!CudaDeviceAvailable(&why)) {
    std::printf("%s: no CUDA device to run on (%s)\n", name, why.c_str());
    return 0;
  }
  std::printf("device: %s\n", why.c_str());
  return RunSelectedBenchmarks(argc, argv);
}

}  // namespace cuda
}  // namespace es

// Defines main() as RunCudaBenchmarks(name, ...), as BENCHMARK_MAIN() does
// for Google Benchmark's own.
#define ES_CUDA_BENCHMARK_MAIN(name)                        \
  int main(int argc, char** argv) {                         \
    return ::es::cuda::RunCudaBenchmarks(name, argc, argv); \
  }

#endif  // EULERSPLAT_APPS_CUDA_CUDA_BENCHMARK_MAIN_H_
