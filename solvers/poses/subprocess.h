#ifndef EULERSPLAT_SOLVERS_POSES_SUBPROCESS_H_
#define EULERSPLAT_SOLVERS_POSES_SUBPROCESS_H_

#include <string>
#include <vector>

namespace es {

// Runs argv[0] (looked up on PATH when it has no '/') with arguments
// argv[1...], no shell, stdout and stderr appended to `log_path`. Returns
// its exit status (128 + signal when killed, 127 when it cannot be
// started).
int RunLogged(const std::vector<std::string>& argv,
              const std::string& log_path);

// The last `lines` lines of a text file (for failure messages).
std::string TailOfFile(const std::string& path, int lines);

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_POSES_SUBPROCESS_H_
