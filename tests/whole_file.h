#ifndef EULERSPLAT_TESTS_WHOLE_FILE_H_
#define EULERSPLAT_TESTS_WHOLE_FILE_H_

#include <fstream>
#include <iterator>
#include <string>

namespace es {

// A file's bytes ("" where it cannot be read), for the tests that compare
// or rewrite files whole.
inline std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void WriteWholeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_WHOLE_FILE_H_
