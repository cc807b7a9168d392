// `surfcap-precompute transitions`: glue between the CLI and graph::transition_similarity.
#include <algorithm>
#include <map>
#include <memory>

#include "commands.hpp"
#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/graph/graph_config.hpp"
#include "surfcap/graph/transition_files.hpp"
#include "surfcap/graph/transition_similarity.hpp"

#include <spdlog/spdlog.h>

namespace surfcap::tools {
namespace {

struct TransitionsArguments {
  std::string database;
  std::string graph;
  std::string output;
  std::vector<std::string> edges;
  std::string report;
  graph::TransitionOptions options;
};

/// The edges to compute: every transition of the config, or the --edge FROM:TO ones (declared).
std::vector<graph::TransitionConfig> selected_edges(const graph::GraphConfig& config, const TransitionsArguments& arguments) {
  if (arguments.edges.empty()) return config.transitions;
  std::vector<graph::TransitionConfig> edges;
  for (const std::string& edge : arguments.edges) {
    const auto colon = edge.find(':');
    if (colon == std::string::npos) throw core::bad_arguments("--edge " + edge + ": expected FROM:TO");
    graph::TransitionConfig wanted{edge.substr(0, colon), edge.substr(colon + 1)};
    const bool declared = std::any_of(config.transitions.begin(), config.transitions.end(), [&](const auto& t) {
      return t.from == wanted.from && t.to == wanted.to;
    });
    if (!declared) throw core::bad_arguments("--edge " + edge + ": not a transition of " + arguments.graph);
    edges.push_back(wanted);
  }
  return edges;
}

void run_transitions(core::ToolApp& app, const TransitionsArguments& arguments) {
  graph::TransitionOptions options = arguments.options;
  options.threads = app.common().threads;
  options.validate();
  const graph::GraphConfig config = graph::read_graph_config(arguments.graph);
  const std::vector<graph::TransitionConfig> edges = selected_edges(config, arguments);
  core::StageReport report("precompute.transitions");
  long vertices = 0;
  {
    auto timer = report.time("read_database");
    vertices = core::read_database(arguments.database).template_mesh.V.rows();
  }
  const std::filesystem::path output(arguments.output);
  std::map<std::string, std::unique_ptr<blend::StoredSpace>> spaces;
  const auto space = [&](const std::string& name) -> const blend::StoredSpace& {
    auto& slot = spaces[name];
    if (!slot) slot = std::make_unique<blend::StoredSpace>(blend::read_stored_space(output, name, vertices));
    return *slot;
  };
  const core::Json provenance = {{"tool", "surfcap-precompute transitions"}, {"version", core::version()},
                                 {"database", arguments.database}, {"graph_config", arguments.graph},
                                 {"velocity_weight", options.velocity_weight}};
  for (const graph::TransitionConfig& edge : edges) {
    const std::string stem = graph::transition_stem(edge.from, edge.to);
    auto timer = report.time("edge_" + stem);
    const blend::StoredSpace& from = space(edge.from);
    const blend::StoredSpace& to = space(edge.to);
    const graph::TransitionSimilarity similarity = graph::transition_similarity(from, to, options);
    graph::write_transition(output, from, to, similarity, provenance);
    report.figures()["transitions"][stem] = similarity.figures;
    spdlog::info("transition {} → {}: {}×{} similarities, best {:.3f}", edge.from, edge.to, similarity.rows,
                 similarity.cols, similarity.figures["best"]["similarity"].get<double>());
  }
  report.figures()["edges"] = edges.size();
  std::string report_path = arguments.report;
  if (report_path.empty()) {
    std::string suffix;
    for (const auto& edge : arguments.edges) suffix += "_" + graph::transition_stem(edge.substr(0, edge.find(':')),
                                                                                    edge.substr(edge.find(':') + 1));
    report_path = (output / "report" / ("transitions" + suffix + ".json")).string();
  }
  report.write(report_path);
}

}  // namespace

Command add_transitions_command(core::ToolApp& app) {
  auto arguments = std::make_shared<TransitionsArguments>();
  CLI::App* command = app.cli().add_subcommand(
      "transitions", "Shape and motion similarity between the reference sequences of connected motion spaces");
  command->add_option("--database", arguments->database, "Aligned database (database.json)")->required();
  command->add_option("--graph", arguments->graph, "Graph config (configs/graphs/*.json)")->required();
  command->add_option("--output,-o", arguments->output,
                      "Output directory of `spaces` (reads spaces/, writes transitions/)")->required();
  command->add_option("--edge", arguments->edges, "Only these transitions FROM:TO (repeatable); default: all")
      ->take_all();
  command->add_option("--report", arguments->report,
                      "Report JSON; default <output>/report/transitions[_FROM__TO...].json");
  command->add_option("--velocity-weight", arguments->options.velocity_weight,
                      "λ of the distance: weight of the velocity term (velocities in m per captured frame)")
      ->capture_default_str();
  return {command, [&app, arguments] { run_transitions(app, *arguments); }};
}

}  // namespace surfcap::tools
