// Runs a fuzz target's LLVMFuzzerTestOneInput on files instead of
// libFuzzer's generated inputs: every file named on the command line, and
// every file inside a directory named there. Builds with any compiler, so
// the normal suite replays the seed corpora through each harness, and a
// fuzzer's finding can be reproduced under gdb in a plain build:
//   replay_fuzz_ply build-asan/artifacts/fuzz_ply-crash-...
// A reader that throws anything but InputError, crashes or hangs fails the
// run, exactly as it would under libFuzzer.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

int Replay(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot read\n", file.c_str());
    return 1;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()),
                         bytes.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE_OR_DIR...\n", argv[0]);
    return 2;
  }
  int inputs = 0, errors = 0;
  for (int i = 1; i < argc; ++i) {
    const fs::path path = argv[i];
    if (fs::is_directory(path)) {
      for (const auto& entry : fs::recursive_directory_iterator(path)) {
        if (!entry.is_regular_file()) continue;
        errors += Replay(entry.path());
        ++inputs;
      }
    } else {
      errors += Replay(path);
      ++inputs;
    }
  }
  std::printf("replayed %d input(s)\n", inputs - errors);
  // An empty corpus would make the replay test pass without testing.
  return errors == 0 && inputs > 0 ? 0 : 1;
}
