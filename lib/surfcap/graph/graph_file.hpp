#pragma once
// <output>/graph.json (docs/blend.md): every space's space.json entry in config order, the
// transitions and the provenance.
#include <filesystem>

#include "surfcap/core/json_document.hpp"
#include "surfcap/graph/graph_config.hpp"

namespace surfcap::graph {

/// Writes <output>/graph.json from every space's space.json when all spaces of `config` are
/// present; returns false (and writes nothing) otherwise.
bool write_graph(const std::filesystem::path& output, const GraphConfig& config, const core::Json& provenance);

}  // namespace surfcap::graph
