#include "core/io/output_dir.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/base/input_error.h"

namespace es {

void PrepareOutputDirectory(const std::string& dir, const std::string& flag) {
  const std::string name = "--" + flag + "=" + dir;
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw InputError(name + ": cannot create the directory (" +
                     error.message() + ")");
  }
  if (!std::filesystem::is_directory(dir)) {
    throw InputError(name + ": exists and is not a directory");
  }
  const std::string probe = dir + "/.write_test." + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    throw InputError(name + ": cannot write in the directory (" +
                     std::strerror(errno) + ")");
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace es
