// libFuzzer target: graph.json of surfcap-precompute, read as asset::assemble_character reads it:
// every space entry (blend::stored_space_from_entry: names, sizes, parameter map, paths of its
// arrays under the path policy) and the transitions' names.
#include "fuzz_documents.hpp"
#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/input_policy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  const auto folder = fuzz::scratch_folder() / "graph";
  const auto path = fuzz::document_file(folder, "graph.json", data, size);
  fuzz::run_reader([&] {
    const core::Json graph = core::read_json_document(path, "graph", 1);
    core::read_document_fields(path, [&] {
      for (const core::Json& entry : core::get_field<core::Json>(graph, "spaces", path)) {
        try {
          blend::stored_space_from_entry(entry, folder, path, fuzz::fixture_character().vertex_count());
        } catch (const core::Error&) {
        }
      }
      for (const core::Json& entry : graph.value("transitions", core::Json::array())) {
        core::name_field(entry, "from", path);
        core::name_field(entry, "to", path);
      }
      return 0;
    });
  });
  return 0;
}
