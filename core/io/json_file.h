#ifndef EULERSPLAT_CORE_IO_JSON_FILE_H_
#define EULERSPLAT_CORE_IO_JSON_FILE_H_

#include <nlohmann/json.hpp>
#include <string>

namespace es {

// Writes `value` to `path` as indented JSON, keys in insertion order,
// atomically (atomic_file.h): NaN and infinity, which JSON lacks, become
// null, and invalid UTF-8 in a string (a path) is replaced, so the file
// always parses. Throws InputError
// naming `path` if it cannot be written (disk full included).
void WriteJsonFile(const std::string& path,
                   const nlohmann::ordered_json& value);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_JSON_FILE_H_
