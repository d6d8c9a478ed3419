#include "apps/common/flag_help.h"

#include <cstdlib>
#include <sstream>
#include <vector>

#include "core/base/number_text.h"

namespace es {
namespace {

constexpr int kWidth = 80;
constexpr int kIndent = 6;

// `text` as lines of at most kWidth columns, each indented by kIndent.
std::string Wrap(const std::string& text) {
  std::istringstream words(text);
  std::string out, line, word;
  while (words >> word) {
    if (!line.empty() &&
        kIndent + line.size() + 1 + word.size() > static_cast<size_t>(kWidth)) {
      out += std::string(kIndent, ' ') + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += std::string(kIndent, ' ') + line + "\n";
  return out;
}

std::string Describe(const gflags::CommandLineFlagInfo& flag) {
  return "  --" + flag.name + " (" + flag.type + ", default " +
         ReadableDefault(flag) + ")\n" + Wrap(flag.description);
}

}  // namespace

bool IsAppFlag(const gflags::CommandLineFlagInfo& flag) {
  const std::string& f = flag.filename;
  return f.rfind("apps/", 0) == 0 || f.find("/apps/") != std::string::npos;
}

std::string ReadableDefault(const gflags::CommandLineFlagInfo& flag) {
  if (flag.type == "string") return "\"" + flag.default_value + "\"";
  if (flag.type == "double") {
    return ShortNumber(std::strtod(flag.default_value.c_str(), nullptr));
  }
  return flag.default_value;
}

std::string FlagHelp(const std::string& usage, bool all) {
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);  // sorted by file, then name
  std::string out = usage + "\n\nFlags:\n";
  for (const auto& flag : flags) {
    if (IsAppFlag(flag)) out += Describe(flag);
  }
  out +=
      "\nAlso: --help (this text), --helpfull (adds glog's and gflags' "
      "flags), --version.\nA flag is --name=value or --name value; a "
      "boolean is --name or --noname.\n";
  if (all) {
    out += "\nglog and gflags flags:\n";
    for (const auto& flag : flags) {
      if (!IsAppFlag(flag)) out += Describe(flag);
    }
  }
  return out;
}

}  // namespace es
