// `surfcap-precompute compare`: casas2011 Table 1 for two poses.
#include <memory>

#include "commands.hpp"
#include "surfcap/blend/blend_comparison.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/report.hpp"

namespace surfcap::tools {
namespace {

struct CompareArguments {
  std::string database, template_mesh, positions, output;
  std::vector<std::string> poses;
  blend::BlendComparisonOptions options;
};

/// A frame from "sequence:frame" (database) or "frame" (positions array).
Eigen::MatrixXd load_pose(const CompareArguments& arguments, const core::AlignedDatabase* database,
                          const std::vector<double>& positions, long vertices, const std::string& pose) {
  try {
    if (database) {
      const auto colon = pose.rfind(':');
      if (colon == std::string::npos) throw core::bad_arguments("--pose must be sequence:frame with --database");
      const int sequence = database->sequence_index(pose.substr(0, colon));
      const int frame = std::stoi(pose.substr(colon + 1));
      if (sequence < 0 || frame < 0 || frame >= database->sequences[sequence].frame_count())
        throw core::bad_arguments("--pose " + pose + ": no such sequence or frame");
      return database->sequences[sequence].frames[frame];
    }
    const long frame = std::stol(pose);
    const long frames = static_cast<long>(positions.size()) / (vertices * 3);
    if (frame < 0 || frame >= frames) throw core::bad_arguments("--pose " + pose + ": frame out of range");
    Eigen::MatrixXd V(vertices, 3);
    for (long v = 0; v < vertices; ++v)
      for (int c = 0; c < 3; ++c) V(v, c) = positions[static_cast<std::size_t>((frame * vertices + v) * 3 + c)];
    return V;
  } catch (const std::invalid_argument&) {
    throw core::bad_arguments("--pose " + pose + ": not a frame number");
  }
}

void run_compare(const CompareArguments& arguments, int threads) {
  if (arguments.poses.size() != 2) throw core::bad_arguments("compare needs exactly two --pose");
  std::unique_ptr<core::AlignedDatabase> database;
  core::Mesh mesh;
  std::vector<double> positions;
  if (!arguments.database.empty()) {
    database = std::make_unique<core::AlignedDatabase>(core::read_database(arguments.database));
    mesh = database->template_mesh;
  } else if (!arguments.template_mesh.empty() && !arguments.positions.empty()) {
    core::MeshRequirements requirements;
    requirements.allow_non_manifold = true;
    requirements.allow_zero_area_faces = true;
    mesh = core::read_mesh(arguments.template_mesh, requirements);
    positions = core::read_npy_as_double(arguments.positions, {-1, mesh.V.rows(), 3});
  } else {
    throw core::bad_arguments("compare needs --database, or --template and --positions");
  }
  const Eigen::MatrixXd a = load_pose(arguments, database.get(), positions, mesh.V.rows(), arguments.poses[0]);
  const Eigen::MatrixXd b = load_pose(arguments, database.get(), positions, mesh.V.rows(), arguments.poses[1]);
  blend::BlendComparisonOptions options = arguments.options;
  options.threads = threads;
  core::StageReport report("precompute.compare");
  report.figures()["comparison"] = blend::compare_blends(mesh, a, b, options);
  report.figures()["poses"] = arguments.poses;
  report.write(arguments.output);
}

}  // namespace

Command add_compare_command(core::ToolApp& app) {
  auto arguments = std::make_shared<CompareArguments>();
  CLI::App* command =
      app.cli().add_subcommand("compare", "casas2011 Table 1: linear / hybrid vs exact non-linear blend of two poses");
  command->add_option("--database", arguments->database, "Aligned database (poses are sequence:frame)");
  command->add_option("--template", arguments->template_mesh, "Template mesh (with --positions)");
  command->add_option("--positions", arguments->positions, "float32 [T, V, 3] positions (poses are frame numbers)");
  command->add_option("--pose", arguments->poses, "The two poses to blend")->take_all();
  command->add_option("--output,-o", arguments->output, "Report JSON")->required();
  command->add_option("--weight-step", arguments->options.weight_step, "Weights where errors are measured")
      ->capture_default_str();
  return {command, [&app, arguments] { run_compare(*arguments, app.common().threads); }};
}

}  // namespace surfcap::tools
