#ifndef EULERSPLAT_CORE_IO_OUTPUT_DIR_H_
#define EULERSPLAT_CORE_IO_OUTPUT_DIR_H_

#include <string>

namespace es {

// Creates `dir` (and its parents) and proves it writable by creating and
// removing a file in it, so a run fails at once rather than after hours of
// training. Throws InputError naming `flag` (without dashes) and `dir`.
void PrepareOutputDirectory(const std::string& dir, const std::string& flag);

// The same for the folder of the file `path` (the current one if it names
// none), and refuses a path that is an existing directory: a tool that
// writes one file checks it before loading or computing anything. Throws
// InputError naming `flag` and `path`.
void PrepareOutputFile(const std::string& path, const std::string& flag);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_OUTPUT_DIR_H_
