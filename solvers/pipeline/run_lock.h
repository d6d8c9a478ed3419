#ifndef EULERSPLAT_SOLVERS_PIPELINE_RUN_LOCK_H_
#define EULERSPLAT_SOLVERS_PIPELINE_RUN_LOCK_H_

#include <string>

namespace es {

// An exclusive lock on an output directory (flock on DIR/.eulersplat.lock),
// held while the object lives. The kernel drops it when the process dies,
// kill -9 included, so a stale lock never blocks a rerun. The descriptor is
// close-on-exec: children do not inherit it.
class RunLock {
 public:
  enum class Mode { kFailIfHeld, kWaitIfHeld };
  // Creates dir if needed. kFailIfHeld throws InputError naming dir when
  // another process holds it; kWaitIfHeld prints a line and waits.
  RunLock(const std::string& dir, Mode mode);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_PIPELINE_RUN_LOCK_H_
