#include "surfcap/graph/graph_file.hpp"

namespace surfcap::graph {

bool write_graph(const std::filesystem::path& output, const GraphConfig& config, const core::Json& provenance) {
  core::Json spaces = core::Json::array();
  for (const blend::SpaceConfig& space : config.spaces) {
    const std::filesystem::path path = output / "spaces" / space.name / "space.json";
    if (!std::filesystem::exists(path)) return false;
    spaces.push_back(core::read_json_document(path, "space", 1).at("space"));
  }
  core::Json transitions = core::Json::array();
  for (const auto& transition : config.transitions) transitions.push_back({{"from", transition.from}, {"to", transition.to}});
  core::Json graph = {{"format", core::format_tag("graph", 1)}, {"spaces", spaces}, {"transitions", transitions},
                      {"provenance", provenance}};
  core::write_json_file(output / "graph.json", graph);
  return true;
}

}  // namespace surfcap::graph
