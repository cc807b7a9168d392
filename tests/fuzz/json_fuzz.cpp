// libFuzzer target: the JSON readers (documents, capture + cameras, database, CLI config files).
#include <sstream>

#include "fuzz_support.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t which = data[0] % 4;
  const auto path = surfcap::fuzz::scratch_file(data + 1, size - 1, ".json");
  try {
    switch (which) {
      case 0: surfcap::core::read_json_document(path, "graph", 1); break;
      case 1: surfcap::core::read_capture(path); break;
      case 2: surfcap::core::read_database(path); break;
      default: {
        std::istringstream input(std::string(reinterpret_cast<const char*>(data + 1), size - 1));
        surfcap::core::JsonConfig().from_config(input);
      }
    }
  } catch (const surfcap::core::Error&) {
  }
  return 0;
}
