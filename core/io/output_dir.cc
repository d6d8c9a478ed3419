#include "core/io/output_dir.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/base/input_error.h"

namespace es {

namespace {

// Creates `dir` and proves it writable; `name` ("--flag=value") and `what`
// ("the directory", "its directory DIR") word the InputError.
void Prepare(const std::string& dir, const std::string& name,
             const std::string& what) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw InputError(name + ": cannot create " + what + " (" +
                     error.message() + ")");
  }
  if (!std::filesystem::is_directory(dir)) {
    throw InputError(name + ": " + dir + " exists and is not a directory");
  }
  const std::string probe = dir + "/.write_test." + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    throw InputError(name + ": cannot write in " + what + " (" +
                     std::strerror(errno) + ")");
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace

void PrepareOutputDirectory(const std::string& dir, const std::string& flag) {
  Prepare(dir, "--" + flag + "=" + dir, "the directory");
}

void PrepareOutputFile(const std::string& path, const std::string& flag) {
  const std::string name = "--" + flag + "=" + path;
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError(name + ": is a directory, not a file name");
  const std::filesystem::path parent =
      std::filesystem::path(path).parent_path();
  const std::string dir = parent.empty() ? "." : parent.string();
  Prepare(dir, name, "its directory " + dir);
}

}  // namespace es
