#ifndef EULERSPLAT_CORE_BASE_ATOMIC_FILE_H_
#define EULERSPLAT_CORE_BASE_ATOMIC_FILE_H_

#include <fstream>
#include <functional>
#include <string>

namespace es {

// Writes `path` so that a crash at any moment leaves either the old file or
// the new one, never a half-written one: `write` fills a temporary file
// beside it (same directory, so the rename stays on one file system), which
// is flushed, checked, fsync'ed and renamed over `path`. A failed write
// (disk full, unwritable directory) throws InputError naming `path`, removes
// the temporary file and keeps the old file.
void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ofstream&)>& write,
                         bool binary = true);

// Text convenience: the whole file content at once.
void WriteTextFileAtomically(const std::string& path,
                             const std::string& content);

// Moves an already written file (e.g. one made by an external encoder) over
// `path` atomically; `from` must be on the same file system.
void ReplaceFile(const std::string& from, const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_ATOMIC_FILE_H_
