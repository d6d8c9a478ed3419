#ifndef EULERSPLAT_TESTS_MEMORY_LIMIT_H_
#define EULERSPLAT_TESTS_MEMORY_LIMIT_H_

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>

#include "core/base/input_error.h"

// AddressSanitizer reserves terabytes of shadow memory up front, so an
// address-space limit cannot be applied under it (gcc and clang spell the
// check differently).
#if defined(__SANITIZE_ADDRESS__)
#define ES_TESTS_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ES_TESTS_UNDER_ASAN 1
#endif
#endif

namespace es {

// Runs `read` in a forked child whose address space may grow by at most
// `extra_bytes` and returns true if it threw InputError: a reader that
// allocates what a corrupt header announces before validating it dies of
// std::bad_alloc there instead (or, under AddressSanitizer, where the limit
// is not applied, trips its allocation-size check).
inline bool ThrowsInputErrorWithinMemory(const std::function<void()>& read,
                                         size_t extra_bytes = 256u << 20) {
  const pid_t pid = ::fork();
  if (pid == 0) {
#ifndef ES_TESTS_UNDER_ASAN
    std::ifstream status("/proc/self/status");
    std::string key;
    size_t vm_kb = 0;
    while (status >> key) {
      if (key == "VmSize:") {
        status >> vm_kb;
        break;
      }
    }
    const rlim_t limit = vm_kb * 1024 + extra_bytes;
    const rlimit rl = {limit, limit};
    ::setrlimit(RLIMIT_AS, &rl);
#endif
    int code = 1;
    try {
      read();
    } catch (const InputError&) {
      code = 0;
    } catch (...) {
      code = 2;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_MEMORY_LIMIT_H_
