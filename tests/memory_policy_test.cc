#include "apps/common/memory_policy.h"

#include <sys/resource.h>

#include <cstddef>
#include <cstdlib>

#include <gtest/gtest.h>

namespace es {
namespace {

#if defined(__GLIBC__)
long MinorFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// An image-sized buffer freed and allocated again (what the stages do per
// frame) comes back from the process' own memory, not as fresh pages that
// fault one by one.
TEST(MemoryPolicyTest, AFreedImageBufferComesBackWithoutPageFaults) {
  KeepFreedMemory();
  const size_t bytes = size_t{8} << 20;  // 2048 pages
  auto touch = [bytes](char* p) {
    for (size_t i = 0; i < bytes; i += 4096) p[i] = 1;
  };
  char* first = static_cast<char*>(std::malloc(bytes));
  touch(first);
  std::free(first);
  const long before = MinorFaults();
  char* again = static_cast<char*>(std::malloc(bytes));
  touch(again);
  const long faults = MinorFaults() - before;
  std::free(again);
  EXPECT_LT(faults, 64);
}
#endif

}  // namespace
}  // namespace es
