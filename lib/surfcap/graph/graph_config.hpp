#pragma once
// The graph config (configs/graphs/*.json, docs/blend.md): the motion spaces (blend::SpaceConfig)
// and the allowed transitions between them.
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/blend/space_config.hpp"

namespace surfcap::graph {

struct TransitionConfig {
  std::string from, to;
};

struct GraphConfig {
  std::vector<blend::SpaceConfig> spaces;
  std::vector<TransitionConfig> transitions;
  const blend::SpaceConfig* find(const std::string& name) const;
};

/// Reads {"format": "surfcap.graph_config/1", ...}; bad_input names the file and field.
GraphConfig read_graph_config(const std::filesystem::path& path);

}  // namespace surfcap::graph
