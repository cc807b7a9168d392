#include "surfcap/learn/leave_out.hpp"

#include <algorithm>
#include <chrono>
#include <set>

#include "surfcap/core/error.hpp"
#include <spdlog/spdlog.h>

namespace surfcap::learn {

void LeaveOutOptions::validate() const {
  if (stride < 2) throw core::bad_arguments("leave-out stride must be ≥ 2 (some frames must be held out)");
  if (max_evaluated < 0) throw core::bad_arguments("max evaluated frames must be ≥ 0");
  if (regions.empty()) throw core::bad_arguments("leave-out needs at least one constrained region");
  learn.validate();
  editor.validate();
}

const MethodError& LeaveOutResult::method(const std::string& name) const {
  for (const auto& m : methods)
    if (m.method == name) return m;
  throw core::internal_error("no leave-out result for method " + name);
}

LeaveOutResult leave_out_evaluation(const core::AlignedDatabase& database, const PartSet& parts,
                                    const LeaveOutOptions& options) {
  options.validate();
  const long n = database.template_mesh.vertex_count();
  const std::vector<ExampleFrame> training = strided_frames(database, options.stride);
  std::vector<ExampleFrame> held_out;
  for (const ExampleFrame& f : all_frames(database))
    if (std::find(training.begin(), training.end(), f) == training.end()) held_out.push_back(f);
  if (held_out.empty()) throw core::bad_input("database", "no held-out frames (sequences too short for the stride)");
  if (options.max_evaluated > 0 && static_cast<std::size_t>(options.max_evaluated) < held_out.size()) {
    std::vector<ExampleFrame> spaced;
    for (int k = 0; k < options.max_evaluated; ++k)
      spaced.push_back(held_out[k * held_out.size() / options.max_evaluated]);
    held_out = spaced;
  }
  std::set<int> constrained;
  for (const std::string& name : options.regions) {
    auto found = parts.regions.find(name);
    if (found == parts.regions.end()) throw core::bad_input("parts", "no region named '" + name + "'");
    constrained.insert(found->second.begin(), found->second.end());
  }
  const std::vector<int> vertices(constrained.begin(), constrained.end());
  const std::vector<double> weights(vertices.size(), 1.0);

  LeaveOutResult result;
  result.training_frames = static_cast<int>(training.size());
  result.evaluated_frames = static_cast<int>(held_out.size());
  result.constrained_vertices = static_cast<long>(vertices.size());
  const LearntModel part_model = learn_part_models(database, parts, training, options.learn);
  const LearntModel global_model = learn_part_models(database, whole_mesh_part(n), training, options.learn);
  struct Candidate {
    std::string name;
    const LearntModel* model;
    EditMethod method;
  };
  const Candidate candidates[] = {{"laplacian", &global_model, EditMethod::laplacian},
                                  {"global", &global_model, EditMethod::learnt},
                                  {"parts", &part_model, EditMethod::learnt}};
  for (const Candidate& candidate : candidates) {
    EditorOptions editor_options = options.editor;
    editor_options.method = candidate.method;
    const PartEditor editor(*candidate.model, editor_options);
    const auto handles = editor.prepare(vertices, weights);
    MethodError error;
    error.method = candidate.name;
    if (candidate.method == EditMethod::learnt)
      for (const auto& p : candidate.model->parts) error.basis_size += p.basis.cols();
    double seconds = 0, sum = 0;
    for (const ExampleFrame& f : held_out) {
      const Eigen::MatrixXd& truth = database.sequences[f.sequence].frames[f.frame];
      Eigen::MatrixXd targets(static_cast<Eigen::Index>(vertices.size()), 3);
      for (std::size_t i = 0; i < vertices.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = truth.row(vertices[i]);
      const auto start = std::chrono::steady_clock::now();
      const Eigen::MatrixXd edited = editor.solve(*handles, targets);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const Eigen::VectorXd distance = (edited - truth).rowwise().norm();
      sum += distance.sum();
      error.max_error = std::max(error.max_error, distance.maxCoeff());
    }
    error.mean_error = sum / (static_cast<double>(held_out.size()) * n);
    error.seconds_per_edit = seconds / held_out.size();
    spdlog::info("leave-out {}: mean {:.2f} mm, max {:.2f} mm, {:.2f} ms/edit", error.method, 1e3 * error.mean_error,
                 1e3 * error.max_error, 1e3 * error.seconds_per_edit);
    result.methods.push_back(error);
  }
  return result;
}

}  // namespace surfcap::learn
