// `surfcap-precompute spaces`: glue between the CLI and blend::build_motion_space.
#include <memory>

#include "commands.hpp"
#include "surfcap/blend/motion_space.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/logging.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/graph/graph_config.hpp"
#include "surfcap/graph/graph_file.hpp"

#include <spdlog/spdlog.h>

namespace surfcap::tools {
namespace {

struct SpacesArguments {
  std::string database;
  std::string graph;
  std::string output;
  std::vector<std::string> spaces;
  std::string report;
  bool no_graph = false;
  blend::MotionSpaceOptions options;
};

struct GraphArguments {
  std::string database;
  std::string graph;
  std::string output;
};

core::Json graph_provenance(const std::string& database, const std::string& graph) {
  return {{"tool", "surfcap-precompute"}, {"version", core::version()}, {"database", database}, {"graph_config", graph}};
}

void run_spaces(core::ToolApp& app, const SpacesArguments& arguments) {
  blend::MotionSpaceOptions options = arguments.options;
  options.threads = app.common().threads;
  options.validate();
  const graph::GraphConfig config = graph::read_graph_config(arguments.graph);
  std::vector<const blend::SpaceConfig*> selected;
  if (arguments.spaces.empty()) {
    for (const auto& space : config.spaces) selected.push_back(&space);
  } else {
    for (const auto& name : arguments.spaces) {
      const blend::SpaceConfig* space = config.find(name);
      if (!space) throw core::bad_arguments("--space " + name + ": not declared in " + arguments.graph);
      selected.push_back(space);
    }
  }
  core::StageReport report("precompute.spaces");
  core::AlignedDatabase database;
  {
    auto timer = report.time("read_database");
    database = core::read_database(arguments.database);
  }
  // What the config asks of every selected space is checked before any is built, so that a bad
  // space leaves no outputs of the spaces before it.
  const long V = database.template_mesh.vertex_count();
  for (const blend::SpaceConfig* space : selected) {
    for (const blend::ParameterSpec& spec : space->parameters)
      for (int v : spec.vertices)
        if (v < 0 || v >= V)
          throw core::bad_input(space->source, "space '" + space->name + "': parameter '" + spec.name + "' names vertex " +
                                                   std::to_string(v) + ", the template has " + std::to_string(V));
    if (space->frames > 0)
      core::check_memory(space->source, "space '" + space->name + "' (" + std::to_string(space->frames) +
                                            " normalised frames of " + std::to_string(space->sequences.size()) +
                                            " sequences, " + std::to_string(V) + " vertices)",
                         4.0 * sizeof(double) * static_cast<double>(space->sequences.size()) * space->frames * V * 3);
  }
  std::unique_ptr<blend::NonlinearBlender> blender;
  {
    auto timer = report.time("factor_template");
    blender = std::make_unique<blend::NonlinearBlender>(database.template_mesh);
  }
  const std::filesystem::path output(arguments.output);
  for (const blend::SpaceConfig* config_space : selected) {
    spdlog::info("space '{}': {} sequences", config_space->name, config_space->sequences.size());
    blend::MotionSpace space;
    {
      auto timer = report.time("space_" + config_space->name);
      space = blend::build_motion_space(database, *blender, *config_space, options);
      blend::write_motion_space(output, space);
    }
    report.figures()["spaces"][config_space->name] = space.figures;
    spdlog::info("space '{}': {} references, {} bytes of displacements, max checked error {:.2f} mm",
                 config_space->name, space.hybrid->reference_count(), space.hybrid->memory_bytes(),
                 1000 * space.hybrid->checked_max_error());
  }
  const bool complete =
      !arguments.no_graph && graph::write_graph(output, config, graph_provenance(arguments.database, arguments.graph));
  report.figures()["graph_written"] = complete;
  if (!complete && !arguments.no_graph)
    spdlog::info("graph.json not written yet: other spaces of the config are still missing");
  std::string report_path = arguments.report;
  if (report_path.empty()) {
    std::string suffix;
    for (const auto& name : arguments.spaces) suffix += "_" + name;
    report_path = (output / "report" / ("spaces" + suffix + ".json")).string();
  }
  report.write(report_path);
}

void run_graph(const GraphArguments& arguments) {
  const graph::GraphConfig config = graph::read_graph_config(arguments.graph);
  const std::filesystem::path output(arguments.output);
  for (const blend::SpaceConfig& space : config.spaces) {
    const auto path = output / "spaces" / space.name / "space.json";
    if (!std::filesystem::exists(path))
      throw core::io_error(path, "missing: run `surfcap-precompute spaces --space " + space.name + "` first");
  }
  graph::write_graph(output, config, graph_provenance(arguments.database, arguments.graph));
  spdlog::info("{} spaces, {} transitions → {}", config.spaces.size(), config.transitions.size(),
               (output / "graph.json").string());
}

}  // namespace

Command add_spaces_command(core::ToolApp& app) {
  auto arguments = std::make_shared<SpacesArguments>();
  CLI::App* command = app.cli().add_subcommand("spaces", "Build the parametric motion spaces of a graph config");
  command->add_option("--database", arguments->database, "Aligned database (database.json)")->required();
  command->add_option("--graph", arguments->graph, "Graph config (configs/graphs/*.json)")->required();
  command->add_option("--output,-o", arguments->output, "Output directory (graph.json, spaces/<name>/...)")->required();
  command->add_option("--space", arguments->spaces, "Only these spaces (repeatable); default: all")->take_all();
  command->add_option("--report", arguments->report,
                      "Report JSON; default <output>/report/spaces[_<space>...].json");
  command->add_flag("--no-graph", arguments->no_graph,
                    "Do not write graph.json (a pipeline runs `graph` once every space is built)");
  auto& o = arguments->options;
  command->add_option("--sample-step", o.sample_step, "Parameter-map sampling step per axis")->capture_default_str();
  command->add_option("--checks-per-interval", o.checks_per_interval,
                      "Bisection check points per interval: 1 (midpoint) or 3 (quarter points too)")
      ->capture_default_str();
  command->add_option("--max-depth", o.max_depth, "Smallest bisection interval is 2^-depth")->capture_default_str();
  command->add_option("--sparsity-fraction", o.sparsity_fraction,
                      "Store displacements larger than tolerance × fraction")->capture_default_str();
  command->add_option("--validation-samples", o.validation_samples,
                      "Random weights where hybrid and linear errors are reported")->capture_default_str();
  command->add_option("--sweep-mm", o.sweep_tolerances_mm, "Tolerances (mm) of the memory/error sweep")
      ->capture_default_str();
  return {command, [&app, arguments] { run_spaces(app, *arguments); }};
}

Command add_graph_command(core::ToolApp& app) {
  auto arguments = std::make_shared<GraphArguments>();
  CLI::App* command =
      app.cli().add_subcommand("graph", "Write graph.json from the spaces `spaces --space` built one by one");
  command->add_option("--database", arguments->database, "Aligned database the spaces were built from (provenance)")
      ->required();
  command->add_option("--graph", arguments->graph, "Graph config (configs/graphs/*.json)")->required();
  command->add_option("--output,-o", arguments->output, "Output directory holding spaces/<name>/space.json")
      ->required();
  return {command, [arguments] { run_graph(*arguments); }};
}

}  // namespace surfcap::tools
