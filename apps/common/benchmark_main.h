#ifndef EULERSPLAT_APPS_COMMON_BENCHMARK_MAIN_H_
#define EULERSPLAT_APPS_COMMON_BENCHMARK_MAIN_H_

#include <cstdio>
#include <cstring>

#include <benchmark/benchmark.h>

#include "apps/common/memory_policy.h"
#include "apps/common/version.h"

namespace es {

// What BENCHMARK_MAIN does: the benchmark library's flags, then the
// benchmarks they select. Header-only: only the bench_* binaries link the
// library.
inline int RunSelectedBenchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// main() of a Google Benchmark binary: BENCHMARK_MAIN plus --version (the
// version and git commit, as every other binary). --help is the benchmark
// library's own. Freed memory is kept as the apps keep it, so a benchmark
// times what training pays for a call, not page faults.
inline int RunBenchmarks(int argc, char** argv) {
  KeepFreedMemory();
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--version") == 0) {
      std::printf("%s\n", VersionString().c_str());
      return 0;
    }
  }
  return RunSelectedBenchmarks(argc, argv);
}

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_BENCHMARK_MAIN_H_
