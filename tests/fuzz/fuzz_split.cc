// libFuzzer target: a scene's split.txt against a fixed list of frames.
#include "core/io/split.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (int i = 0; i < 12; ++i)
      names.push_back("frame_00000" + std::to_string(i % 10) +
                      (i < 10 ? ".png" : ".jpg"));
    return names;
  }();
  const std::string path = es::WriteFuzzInput("split.txt", data, size);
  es::ReadAllowingRefusal([&] { es::ReadSplitFile(path, kNames); });
  return 0;
}
