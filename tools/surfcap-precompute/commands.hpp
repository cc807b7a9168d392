#pragma once
// Subcommands of surfcap-precompute. Each adds itself to the ToolApp and returns the subcommand
// and the function to run when it was chosen; more (e.g. `transitions`) are added the same way.
#include <functional>
#include <utility>

#include "surfcap/core/cli.hpp"

namespace surfcap::tools {

using Command = std::pair<CLI::App*, std::function<void()>>;

/// `spaces`: parametric motion spaces (time warps, hybrid displacement fields, parameter maps).
Command add_spaces_command(core::ToolApp& app);
/// `graph`: graph.json from spaces built one per job (`spaces --space NAME --no-graph`).
Command add_graph_command(core::ToolApp& app);
/// `compare`: casas2011 Table 1 for two poses (linear / hybrid 1 / hybrid 3 vs exact).
Command add_compare_command(core::ToolApp& app);
/// `transitions`: similarity matrices between connected spaces (casas2013 §3.2).
Command add_transitions_command(core::ToolApp& app);

}  // namespace surfcap::tools
