#ifndef EULERSPLAT_TESTS_WEB_TOOLS_H_
#define EULERSPLAT_TESTS_WEB_TOOLS_H_

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/whole_file.h"

namespace es {

// The npm packages scripts/setup.sh installs (web/package.json) and the
// programs that run them. Tests that need one skip when it is absent.
inline std::string WebModulePath(const std::string& relative) {
  return (std::filesystem::path(ES_SOURCE_DIR) / "web" / "node_modules" /
          relative)
      .string();
}

inline bool HaveWebModule(const std::string& relative) {
  return std::filesystem::exists(WebModulePath(relative));
}

inline bool HaveProgram(const std::string& name) {
  return std::system(("command -v " + name + " > /dev/null 2>&1").c_str()) ==
         0;
}

inline std::string Quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs a shell command with its output in `log`; returns the exit status.
inline int RunLogged(const std::string& command, const std::string& log) {
  const int status =
      std::system((command + " > " + Quoted(log) + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace es

#endif  // EULERSPLAT_TESTS_WEB_TOOLS_H_
