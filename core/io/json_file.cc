#include "core/io/json_file.h"

#include "core/base/atomic_file.h"

namespace es {

void WriteJsonFile(const std::string& path,
                   const nlohmann::ordered_json& value) {
  WriteTextFileAtomically(
      path, value.dump(2, ' ', false,
                       nlohmann::ordered_json::error_handler_t::replace) +
                "\n");
}

}  // namespace es
