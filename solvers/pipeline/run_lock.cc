#include "solvers/pipeline/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/base/input_error.h"

namespace es {

RunLock::RunLock(const std::string& dir, Mode mode) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw InputError(dir + ": cannot create directory");
  const std::string path = dir + "/.eulersplat.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw InputError(path + ": cannot open lock file (" +
                     std::strerror(errno) + ")");
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  if (errno != EWOULDBLOCK) {
    ::close(fd_);
    throw InputError(path + ": cannot lock (" + std::strerror(errno) + ")");
  }
  if (mode == Mode::kFailIfHeld) {
    ::close(fd_);
    throw InputError(dir + ": another eulersplat run is using this directory "
                     "(wait for it to end, or give another --out)");
  }
  std::printf("[eulersplat] %s is in use by another run; waiting for it\n",
              dir.c_str());
  std::fflush(stdout);
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno != EINTR) {
      ::close(fd_);
      throw InputError(path + ": cannot lock (" + std::strerror(errno) + ")");
    }
  }
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace es
