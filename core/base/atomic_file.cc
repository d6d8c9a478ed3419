#include "core/base/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/base/input_error.h"

namespace es {
namespace {

// The temporary name is unique per process so two writers of one path do
// not interleave their bytes.
std::string TempPath(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

// Flushes the file's data to disk so the rename cannot be persisted before
// its content.
bool SyncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

void ReplaceFile(const std::string& from, const std::string& path) {
  if (std::rename(from.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(from.c_str());
    throw InputError(path + ": cannot replace it with " + from + " (" +
                     reason + ")");
  }
}

void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ofstream&)>& write,
                         bool binary) {
  const std::string tmp = TempPath(path);
  {
    std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc
                                  : std::ios::trunc);
    if (!out) {
      throw InputError(path + ": cannot open " + tmp + " for writing (" +
                       std::strerror(errno) + ")");
    }
    write(out);
    // Close before checking: buffered bytes reach the disk only here, and a
    // full disk shows up as a failed close.
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      throw InputError(path + ": write failed (disk full or I/O error)");
    }
  }
  if (!SyncFile(tmp)) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot sync " + tmp + " to disk");
  }
  ReplaceFile(tmp, path);
}

void WriteTextFileAtomically(const std::string& path,
                             const std::string& content) {
  WriteFileAtomically(
      path, [&](std::ofstream& out) { out << content; }, /*binary=*/false);
}

}  // namespace es
