// libFuzzer target: the Stage-1 and joint checkpoint readers (their 8-byte
// tags differ, so both run on every input).
#include "core/base/input_error.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/checkpoint/joint_checkpoint.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = es::WriteFuzzFile(
      "checkpoint.bin", reinterpret_cast<const char*>(data), size);
  try {
    es::ReadCheckpoint(path);
  } catch (const es::InputError&) {
  }
  try {
    es::ReadJointCheckpoint(path);
  } catch (const es::InputError&) {
  }
  return 0;
}
