#ifndef EULERSPLAT_TESTS_FUZZ_FUZZ_INPUT_H_
#define EULERSPLAT_TESTS_FUZZ_FUZZ_INPUT_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/input_error.h"

namespace es {

// The readers take paths, so each fuzz input is written to a file in a
// per-process directory on /dev/shm (memory, not the shared disk).
inline const std::string& FuzzDir() {
  static const std::string dir = [] {
    const std::string d = "/dev/shm/es_fuzz_" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string WriteFuzzFile(const std::string& name, const char* data,
                                 size_t size) {
  const std::string path = FuzzDir() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(data, size);
  return path;
}

// Splits an input into `n` files at the separator "\n@@\n" (listed in the
// dictionaries), so one input can describe a multi-file model; missing
// parts are empty files.
inline std::vector<std::string> SplitFuzzInput(const uint8_t* data,
                                               size_t size, int n) {
  const std::string all(reinterpret_cast<const char*>(data), size);
  static const std::string kSeparator = "\n@@\n";
  std::vector<std::string> parts;
  size_t pos = 0;
  for (int i = 0; i < n; ++i) {
    if (pos == std::string::npos) {
      parts.emplace_back();
      continue;
    }
    const size_t end = i + 1 < n ? all.find(kSeparator, pos) : all.size();
    if (end == std::string::npos) {
      parts.push_back(all.substr(pos));
      pos = std::string::npos;
    } else {
      parts.push_back(all.substr(pos, end - pos));
      pos = end + kSeparator.size();
    }
  }
  return parts;
}

// The whole input as the file `name`; returns its path.
inline std::string WriteFuzzInput(const std::string& name,
                                  const uint8_t* data, size_t size) {
  return WriteFuzzFile(name, reinterpret_cast<const char*>(data), size);
}

// The input split (SplitFuzzInput) into one file per name, in FuzzDir().
inline void WriteFuzzParts(const std::vector<std::string>& names,
                           const uint8_t* data, size_t size) {
  const std::vector<std::string> parts =
      SplitFuzzInput(data, size, static_cast<int>(names.size()));
  for (size_t i = 0; i < names.size(); ++i)
    WriteFuzzFile(names[i], parts[i].data(), parts[i].size());
}

// Runs a reader on the input: refusing it with InputError is a right
// answer; a crash or any other exception is a finding.
template <typename Read>
void ReadAllowingRefusal(Read read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_FUZZ_FUZZ_INPUT_H_
