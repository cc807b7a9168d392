// libFuzzer target: the JSON chunk of a .glb character (asset::parse_character_glb) with the binary
// chunk of the fixture character, so mutations of the glTF JSON and of the SURFCAP_motion_graph
// extension reach every accessor and check.
#include <cstring>

#include "fuzz_documents.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  static const std::string bin_chunk = [] {
    const std::string glb = core::read_file(fuzz::fixture_glb());
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    return glb.substr(20 + json_length);  // length, type and bytes of the BIN chunk
  }();
  std::string json(reinterpret_cast<const char*>(data), size);
  json.append((4 - json.size() % 4) % 4, ' ');
  auto le32 = [](std::uint32_t value) { return std::string(reinterpret_cast<const char*>(&value), 4); };
  const std::string glb = "glTF" + le32(2) + le32(static_cast<std::uint32_t>(20 + json.size() + bin_chunk.size())) +
                          le32(static_cast<std::uint32_t>(json.size())) + "JSON" + json + bin_chunk;
  fuzz::run_reader([&] { asset::parse_character_glb(glb, "fuzz.glb"); });
  return 0;
}
