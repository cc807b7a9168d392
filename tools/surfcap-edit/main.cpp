// surfcap-edit: constrained editing with learnt part-based models (tejera2013 §IV-B).
// Glue only: model + edit file → lib/surfcap/learn PartEditor → edited mesh + report.
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>

#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/learn/edit_file.hpp"
#include "surfcap/learn/part_editor.hpp"

namespace fs = std::filesystem;
using namespace surfcap;

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-edit", "Edit a pose with soft positional constraints in learnt part-based spaces");
  CLI::App& cli = app.cli();
  std::string model_path, edit_path, output, pose_path, method = "part", report_path;
  learn::EditorOptions options;
  cli.add_option("--model", model_path, "parts.json written by surfcap-learn")->required();
  cli.add_option("--edit", edit_path, "edit file (surfcap.edit/1)")->required();
  cli.add_option("--output", output, "edited mesh (.ply/.obj/.off)")->required();
  cli.add_option("--pose", pose_path, "starting pose (same topology as the template; default the template)");
  cli.add_option("--method", method, "part | global (<model dir>/global/parts.json) | laplacian")
      ->check(CLI::IsMember({"part", "global", "laplacian"}))
      ->capture_default_str();
  cli.add_option("--iterations", options.rotation_iterations, "rotation updates of δ")->capture_default_str();
  cli.add_option("--weight", options.constraint_weight, "weight of a constraint of weight 1")->capture_default_str();
  cli.add_option("--frontier-weight", options.frontier_weight, "weight of the frontier anchors")->capture_default_str();
  cli.add_option("--regularisation", options.regularisation, "pull of the basis coefficients to the pose's")
      ->capture_default_str();
  cli.add_option("--report", report_path, "report JSON (default <output>.report.json)");

  return app.run(argc, argv, [&] {
    core::StageReport report("edit");
    const fs::path parts_json = method == "global" ? fs::path(model_path).parent_path() / "global" / "parts.json"
                                                   : fs::path(model_path);
    const learn::LearntModel model = learn::read_learnt_model(parts_json);
    core::Mesh mesh = model.template_mesh;
    if (!pose_path.empty()) {
      const core::Mesh pose = core::read_mesh(pose_path);
      if (pose.vertex_count() != mesh.vertex_count())
        throw core::bad_input(pose_path, "has " + std::to_string(pose.vertex_count()) + " vertices, the template " +
                                             std::to_string(mesh.vertex_count()));
      mesh.V = pose.V;
    }
    const std::vector<learn::Constraint> constraints = learn::edit_constraints(
        core::read_json_document(edit_path, "edit", 1), model.part_set(), mesh.V, edit_path);
    options.method = method == "laplacian" ? learn::EditMethod::laplacian : learn::EditMethod::learnt;
    auto setup = report.time("setup");
    const learn::PartEditor editor(model, options, mesh.V);
    setup.stop();
    std::vector<int> vertices;
    std::vector<double> weights;
    std::map<int, std::size_t> last;
    for (std::size_t k = 0; k < constraints.size(); ++k) last[constraints[k].vertex] = k;
    Eigen::MatrixXd targets(static_cast<Eigen::Index>(last.size()), 3);
    for (const auto& [v, k] : last) {
      targets.row(static_cast<Eigen::Index>(vertices.size())) = constraints[k].target.transpose();
      vertices.push_back(v);
      weights.push_back(constraints[k].weight);
    }
    auto prepare = report.time("prepare");
    const auto handles = editor.prepare(vertices, weights);
    prepare.stop();
    const auto start = std::chrono::steady_clock::now();
    const Eigen::MatrixXd edited = editor.solve(*handles, targets);
    report.add_timing("edit", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    double residual = 0;
    for (std::size_t i = 0; i < vertices.size(); ++i)
      residual = std::max(residual, (edited.row(vertices[i]) - targets.row(static_cast<Eigen::Index>(i))).norm());
    if (!edited.allFinite() || edited.cwiseAbs().maxCoeff() > core::kMaxCoordinate)
      throw core::bad_input(edit_path, "the edit moves vertices beyond the plausible magnitude (" +
                                           std::to_string(static_cast<long>(core::kMaxCoordinate)) + " m)");
    const Eigen::VectorXd moved = (edited - mesh.V).rowwise().norm();
    mesh.V = edited;
    core::write_mesh(output, mesh);
    report.figures()["method"] = method;
    report.figures()["constrained_vertices"] = vertices.size();
    report.figures()["max_constraint_residual_mm"] = 1e3 * residual;
    report.figures()["max_displacement_mm"] = 1e3 * moved.maxCoeff();
    report.figures()["moved_vertices_over_1mm"] = (moved.array() > 1e-3).count();
    report.write(report_path.empty() ? fs::path(output + ".report.json") : fs::path(report_path));
    spdlog::info("edited {} vertices ({} constrained) with method {}", mesh.vertex_count(), vertices.size(), method);
  });
}
