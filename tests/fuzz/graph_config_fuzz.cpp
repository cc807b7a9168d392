// libFuzzer target: graph configs (graph::read_graph_config, configs/graphs/*.json).
#include "fuzz_documents.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/graph/graph_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  const auto path = fuzz::document_file(fuzz::scratch_folder() / "graph_config", "graph.json", data, size);
  fuzz::run_reader([&] {
    const graph::GraphConfig config = graph::read_graph_config(path);
    for (const auto& space : config.spaces) {
      core::check_name(path, "name", space.name);  // it names an output folder: must not throw
      if (space.degree < 0 || space.degree > 16 || space.frames < 0) __builtin_trap();
      for (const auto& parameter : space.parameters)
        for (int v : parameter.vertices)
          if (v < 0) __builtin_trap();
    }
  });
  return 0;
}
