// libFuzzer target: the Stage-1 and joint checkpoint readers (their 8-byte
// tags differ, so both run on every input).
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzInput("checkpoint.bin", data, size);
  es::ReadAllowingRefusal([&] { es::ReadCheckpoint(path); });
  es::ReadAllowingRefusal([&] { es::ReadJointCheckpoint(path); });
  return 0;
}
