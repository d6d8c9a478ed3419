#ifndef EULERSPLAT_APPS_COMMON_FLAG_HELP_H_
#define EULERSPLAT_APPS_COMMON_FLAG_HELP_H_

#include <gflags/gflags.h>

#include <string>

namespace es {

// True for a flag defined by an app (a DEFINE_* in apps/), false for the
// flags glog and gflags bring along.
bool IsAppFlag(const gflags::CommandLineFlagInfo& flag);

// The flag's default as a person writes it: 0.000125 rather than gflags'
// 0.00012500000000000001, "" for an empty string.
std::string ReadableDefault(const gflags::CommandLineFlagInfo& flag);

// `usage`, then every app flag (name, type, default, description wrapped to
// 80 columns), then a line on the common flags. With `all`, glog's and
// gflags' flags follow.
std::string FlagHelp(const std::string& usage, bool all);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_FLAG_HELP_H_
