#include "surfcap/learn/part_editor.hpp"

#include <algorithm>
#include <map>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/cotangent_laplacian.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::learn {

void EditorOptions::validate() const {
  if (rotation_iterations < 0) throw core::bad_arguments("rotation iterations must be ≥ 0");
  if (!(constraint_weight > 0) || !(frontier_weight > 0)) throw core::bad_arguments("constraint weights must be > 0");
  if (!(regularisation > 0)) throw core::bad_arguments("regularisation must be > 0");
}

struct PartEditor::PartSpace {
  std::vector<int> vertices;         ///< local → global
  std::vector<int> global_to_local;  ///< −1 outside the part
  std::vector<int> frontier_local;
  Eigen::VectorXd blend;             ///< weight of this part over its parent's result
  Eigen::SparseMatrix<double> L;
  std::array<Eigen::MatrixXd, 3> basis;
  Eigen::MatrixXd g;
  Eigen::VectorXd r0;
  std::unique_ptr<LearntLaplacianSpace> space;
};

class PreparedHandles {
 public:
  std::vector<int> vertices;
  std::vector<double> weights;
  // Per part: the user constraints it holds (index into vertices) and its prepared space.
  std::vector<std::vector<std::pair<int, int>>> user;  ///< (local vertex, constraint index)
  std::vector<std::unique_ptr<LearntLaplacianSpace::Prepared>> prepared;
  std::unique_ptr<LearntLaplacianSpace::Prepared> coupled;
};

namespace {

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& X, const std::vector<int>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), X.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = X.row(rows[i]);
  return out;
}

}  // namespace

PartEditor::PartEditor(PartEditor&&) noexcept = default;
PartEditor::~PartEditor() = default;

PartEditor::PartEditor(const LearntModel& model, const EditorOptions& options, const Eigen::MatrixXd& reference)
    : options_(options), reference_(reference.size() ? reference : model.template_mesh.V) {
  options_.validate();
  const core::Mesh& mesh = model.template_mesh;
  const long n = mesh.vertex_count();
  if (reference_.rows() != n || reference_.cols() != 3)
    throw core::bad_input("reference pose", "has " + std::to_string(reference_.rows()) + " vertices, the model " +
                                                std::to_string(n));
  if (options_.method == EditMethod::laplacian) {
    PartModel whole;
    whole.part = whole_mesh_part(n).parts[0];
    parts_.push_back(std::move(whole));
  } else {
    parts_ = model.parts;
  }
  const auto adjacency = geometry::vertex_adjacency(mesh.F, n);
  for (const PartModel& pm : parts_) {
    auto ps = std::make_unique<PartSpace>();
    const auto sub = geometry::extract_submesh(mesh.F, n, pm.part.vertices);
    ps->vertices = sub.vertices;
    ps->global_to_local = sub.global_to_local;
    for (int v : pm.part.frontier) ps->frontier_local.push_back(sub.global_to_local[v]);
    ps->blend = frontier_blend_weights(pm.part, adjacency);
    const Eigen::MatrixXd rest = rows_of(mesh.V, sub.vertices);
    ps->L = geometry::cotangent_laplacian(rest, sub.F);
    const Eigen::MatrixXd reference_delta = ps->L * rows_of(reference_, sub.vertices);
    const Eigen::Index nj = rest.rows(), l = pm.basis.cols();
    Eigen::VectorXd delta_flat = Eigen::Map<const Eigen::VectorXd>(reference_delta.data(), 3 * nj);
    if (options_.method == EditMethod::laplacian || l == 0) {
      ps->g = reference_delta;
      for (int c = 0; c < 3; ++c) ps->basis[c].resize(nj, 0);
      ps->r0.resize(0);
    } else {
      if (pm.basis.rows() != 3 * nj || pm.mean.size() != 3 * nj)
        throw core::bad_input("parts model", "part '" + pm.part.name + "' basis does not match its vertices");
      ps->r0 = pm.basis.transpose() * (delta_flat - pm.mean);
      // Keeping the detail, g + E r0 reproduces its δ exactly.
      const Eigen::VectorXd g = options_.keep_detail ? Eigen::VectorXd(delta_flat - pm.basis * ps->r0) : pm.mean;
      ps->g = Eigen::Map<const Eigen::MatrixXd>(g.data(), nj, 3);
      for (int c = 0; c < 3; ++c) ps->basis[c] = pm.basis.middleRows(c * nj, nj);
    }
    auto local_adjacency = geometry::vertex_adjacency(sub.F, nj);
    ps->space = std::make_unique<LearntLaplacianSpace>(ps->L, ps->basis, ps->g, ps->r0, rows_of(reference_, sub.vertices),
                                                       options_.regularisation, std::move(local_adjacency));
    spaces_.push_back(std::move(ps));
  }
  if (spaces_.size() > 1) {
    // Every part's term at once: D = [L_j P_j], E = diag(E_j).
    long rows = 0, columns = 0;
    for (const auto& ps : spaces_) rows += static_cast<long>(ps->vertices.size()), columns += ps->r0.size();
    std::vector<Eigen::Triplet<double>> entries;
    std::array<Eigen::MatrixXd, 3> basis;
    for (auto& b : basis) b = Eigen::MatrixXd::Zero(rows, columns);
    Eigen::MatrixXd g(rows, 3);
    Eigen::VectorXd r0(columns);
    long row = 0, column = 0;
    for (const auto& ps : spaces_) {
      for (int k = 0; k < ps->L.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(ps->L, k); it; ++it)
          entries.emplace_back(row + it.row(), ps->vertices[it.col()], it.value());
      const Eigen::Index nj = static_cast<Eigen::Index>(ps->vertices.size()), l = ps->r0.size();
      for (int c = 0; c < 3; ++c) basis[c].block(row, column, nj, l) = ps->basis[c];
      g.middleRows(row, nj) = ps->g;
      r0.segment(column, l) = ps->r0;
      row += nj, column += l;
    }
    Eigen::SparseMatrix<double> D(rows, n);
    D.setFromTriplets(entries.begin(), entries.end());
    coupled_ = std::make_unique<LearntLaplacianSpace>(std::move(D), std::move(basis), std::move(g), std::move(r0),
                                                      reference_, options_.regularisation,
                                                      std::vector<std::vector<int>>{});
  }
}

std::shared_ptr<const PreparedHandles> PartEditor::prepare(const std::vector<int>& vertices,
                                                           const std::vector<double>& weights) const {
  if (vertices.size() != weights.size()) throw core::internal_error("PartEditor::prepare: vertices/weights mismatch");
  auto handles = std::make_shared<PreparedHandles>();
  handles->vertices = vertices;
  handles->weights = weights;
  handles->user.resize(spaces_.size());
  handles->prepared.resize(spaces_.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    if (vertices[k] < 0 || vertices[k] >= reference_.rows())
      throw core::bad_input("edit", "constraint vertex " + std::to_string(vertices[k]) + " out of range");
    for (std::size_t j = 0; j < spaces_.size(); ++j) {
      const int local = spaces_[j]->global_to_local[vertices[k]];
      if (local >= 0) handles->user[j].emplace_back(local, static_cast<int>(k));
    }
  }
  if (vertices.empty()) return handles;
  for (std::size_t j = 0; j < spaces_.size(); ++j) {
    std::map<int, double> squared;  // local vertex → Σ w² (user constraints and frontier anchors)
    for (const auto& [local, k] : handles->user[j])
      squared[local] += std::pow(options_.constraint_weight * weights[k], 2);
    for (int local : spaces_[j]->frontier_local) squared[local] += std::pow(options_.frontier_weight, 2);
    if (squared.empty()) continue;  // an unconstrained root: placed by the coupled solve
    std::vector<int> local_vertices;
    Eigen::VectorXd w(static_cast<Eigen::Index>(squared.size()));
    for (const auto& [local, w2] : squared) {
      w[static_cast<Eigen::Index>(local_vertices.size())] = std::sqrt(w2);
      local_vertices.push_back(local);
    }
    handles->prepared[j] = spaces_[j]->space->prepare(local_vertices, w);
  }
  if (!handles->prepared[0]) {
    Eigen::VectorXd w(static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t k = 0; k < vertices.size(); ++k) w[static_cast<Eigen::Index>(k)] = options_.constraint_weight * weights[k];
    handles->coupled = coupled_->prepare(vertices, w);
  }
  return handles;
}

Eigen::MatrixXd PartEditor::solve(const PreparedHandles& handles, const Eigen::MatrixXd& targets) const {
  if (targets.rows() != static_cast<Eigen::Index>(handles.vertices.size()))
    throw core::internal_error("PartEditor::solve: targets do not match the handles");
  Eigen::MatrixXd X = reference_;
  if (handles.vertices.empty()) return X;
  for (std::size_t j = 0; j < spaces_.size(); ++j) {
    const PartSpace& ps = *spaces_[j];
    const auto* prepared = handles.prepared[j].get();
    Eigen::MatrixXd part_result;
    if (!prepared) {  // root without constraints of its own
      part_result = rows_of(coupled_->solve(*handles.coupled, targets, 0), ps.vertices);
    } else {
      // Targets in the prepared (sorted local) order: user targets (w²-averaged) and frontier.
      std::map<int, std::pair<Eigen::Vector3d, double>> accumulated;
      for (const auto& [local, k] : handles.user[j]) {
        const double w2 = std::pow(options_.constraint_weight * handles.weights[k], 2);
        auto& [sum, total] = accumulated.try_emplace(local, Eigen::Vector3d::Zero(), 0.0).first->second;
        sum += w2 * targets.row(k).transpose(), total += w2;
      }
      double frontier_change = 0;
      for (int local : ps.frontier_local) {
        const int v = ps.vertices[local];
        const double w2 = options_.frontier_weight * options_.frontier_weight;
        auto& [sum, total] = accumulated.try_emplace(local, Eigen::Vector3d::Zero(), 0.0).first->second;
        sum += w2 * X.row(v).transpose(), total += w2;
        frontier_change = std::max(frontier_change, (X.row(v) - reference_.row(v)).norm());
      }
      // A part whose parent did not move and that holds no constraint keeps its pose.
      if (handles.user[j].empty() && frontier_change < 1e-9) continue;
      Eigen::MatrixXd local_targets(static_cast<Eigen::Index>(prepared->vertices.size()), 3);
      double target_change = 0;
      for (std::size_t i = 0; i < prepared->vertices.size(); ++i) {
        const auto& [sum, total] = accumulated.at(prepared->vertices[i]);
        local_targets.row(static_cast<Eigen::Index>(i)) = (sum / total).transpose();
        target_change = std::max(target_change, (local_targets.row(static_cast<Eigen::Index>(i)) -
                                                 reference_.row(ps.vertices[prepared->vertices[i]])).norm());
      }
      // Keeping the detail, the reference pose is the exact solution when every target is met by it.
      if (options_.keep_detail && target_change < 1e-9) continue;
      part_result = ps.space->solve(*prepared, local_targets, options_.rotation_iterations);
    }
    // Recombination: frontier vertices blend linearly from the parent's result to the part's.
    for (std::size_t i = 0; i < ps.vertices.size(); ++i) {
      const double a = ps.blend[static_cast<Eigen::Index>(i)];
      const int v = ps.vertices[i];
      X.row(v) = (1 - a) * X.row(v) + a * part_result.row(static_cast<Eigen::Index>(i));
    }
  }
  return X;
}

Eigen::MatrixXd PartEditor::edit(const std::vector<Constraint>& constraints) const {
  std::map<int, std::size_t> last;
  for (std::size_t k = 0; k < constraints.size(); ++k) last[constraints[k].vertex] = k;
  std::vector<int> vertices;
  std::vector<double> weights;
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(last.size()), 3);
  for (const auto& [v, k] : last) {
    targets.row(static_cast<Eigen::Index>(vertices.size())) = constraints[k].target.transpose();
    vertices.push_back(v);
    weights.push_back(constraints[k].weight);
  }
  return solve(*prepare(vertices, weights), targets);
}

}  // namespace surfcap::learn
