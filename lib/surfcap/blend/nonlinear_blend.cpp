#include "surfcap/blend/nonlinear_blend.hpp"

#include <Eigen/SparseCholesky>
#include <numeric>

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/geometry/deformation_gradient.hpp"
#include "surfcap/geometry/gradient_operator.hpp"
#include "surfcap/geometry/rotation.hpp"

namespace surfcap::blend {
namespace {

/// Connected components of the vertices through faces (union-find); unreferenced vertices are
/// their own components.
Eigen::VectorXi connected_components(long vertices, const Eigen::MatrixXi& F, int& count) {
  std::vector<int> parent(static_cast<std::size_t>(vertices));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (long k = 0; k < F.rows(); ++k)
    for (int c = 1; c < 3; ++c) {
      const int a = find(F(k, 0)), b = find(F(k, c));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  Eigen::VectorXi component(vertices);
  std::vector<int> label(static_cast<std::size_t>(vertices), -1);
  count = 0;
  for (long v = 0; v < vertices; ++v) {
    const int root = find(static_cast<int>(v));
    if (label[root] < 0) label[root] = count++;
    component(v) = label[root];
  }
  return component;
}

}  // namespace

struct NonlinearBlender::State {
  Eigen::MatrixXi F;
  geometry::DeformationGradient gradients;
  Eigen::SparseMatrix<double> divergence;  // Gᵀ A (n×3m)
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  Eigen::VectorXi component;
  std::vector<long> component_sizes;
  int components = 0;

  State(const core::Mesh& mesh) : F(mesh.F), gradients(mesh.V, mesh.F) {}

  Eigen::MatrixXd centroids(const Eigen::MatrixXd& positions) const {
    Eigen::MatrixXd result = Eigen::MatrixXd::Zero(components, 3);
    for (long v = 0; v < positions.rows(); ++v) result.row(component(v)) += positions.row(v);
    for (int c = 0; c < components; ++c) result.row(c) /= static_cast<double>(component_sizes[c]);
    return result;
  }
};

NonlinearBlender::NonlinearBlender(const core::Mesh& template_mesh)
    : state_(std::make_unique<State>(template_mesh)) {
  State& s = *state_;
  const long n = template_mesh.V.rows();
  s.component = connected_components(n, template_mesh.F, s.components);
  s.component_sizes.assign(static_cast<std::size_t>(s.components), 0);
  for (long v = 0; v < n; ++v) ++s.component_sizes[s.component(v)];
  const Eigen::SparseMatrix<double> G = geometry::gradient_operator(template_mesh.V, template_mesh.F);
  const Eigen::SparseMatrix<double> A = geometry::triangle_area_matrix(template_mesh.V, template_mesh.F);
  s.divergence = Eigen::SparseMatrix<double>(G.transpose()) * A;
  Eigen::SparseMatrix<double> L = s.divergence * G;
  // Pin the first vertex of each component: Gᵀ A g is orthogonal to per-component constants,
  // so the pinned system's solution is the least-squares one with that vertex at the origin.
  const double pin = L.diagonal().cwiseAbs().maxCoeff() > 0 ? L.diagonal().cwiseAbs().mean() : 1.0;
  std::vector<bool> pinned(static_cast<std::size_t>(s.components), false);
  for (long v = 0; v < n; ++v)
    if (!pinned[s.component(v)]) {
      pinned[s.component(v)] = true;
      L.coeffRef(v, v) += pin;
    }
  s.solver.compute(L);
  if (s.solver.info() != Eigen::Success)
    throw core::bad_input("template", "the Poisson system of the template mesh cannot be factored");
}

NonlinearBlender::~NonlinearBlender() = default;
NonlinearBlender::NonlinearBlender(NonlinearBlender&&) noexcept = default;
NonlinearBlender& NonlinearBlender::operator=(NonlinearBlender&&) noexcept = default;

long NonlinearBlender::vertex_count() const { return state_->component.size(); }
long NonlinearBlender::face_count() const { return state_->F.rows(); }
int NonlinearBlender::component_count() const { return state_->components; }
const Eigen::VectorXi& NonlinearBlender::vertex_components() const { return state_->component; }

DecomposedFrame NonlinearBlender::decompose(const Eigen::MatrixXd& positions) const {
  const State& s = *state_;
  if (positions.rows() != vertex_count() || positions.cols() != 3)
    throw core::internal_error("NonlinearBlender::decompose: vertex count differs from the template");
  DecomposedFrame frame;
  const long m = s.F.rows();
  frame.rotations.resize(static_cast<std::size_t>(m));
  frame.stretches.resize(static_cast<std::size_t>(m));
  for (long k = 0; k < m; ++k) {
    const geometry::RotationStretch split = geometry::split_rotation_stretch(s.gradients.triangle(positions, k));
    frame.rotations[static_cast<std::size_t>(k)] = split.rotation;
    frame.stretches[static_cast<std::size_t>(k)] = split.stretch;
  }
  frame.component_centroids = s.centroids(positions);
  return frame;
}

Eigen::MatrixXd NonlinearBlender::reconstruct(const std::vector<Eigen::Matrix3d>& gradients,
                                              const Eigen::MatrixXd& component_centroids) const {
  const State& s = *state_;
  const long m = s.F.rows();
  // Target gradient of coordinate c on triangle k is row c of T_k: rows 3k+d, column c.
  Eigen::MatrixXd target(3 * m, 3);
  for (long k = 0; k < m; ++k) target.block<3, 3>(3 * k, 0) = gradients[static_cast<std::size_t>(k)].transpose();
  const Eigen::MatrixXd rhs = s.divergence * target;
  Eigen::MatrixXd X = s.solver.solve(rhs);
  const Eigen::MatrixXd offset = component_centroids - s.centroids(X);
  for (long v = 0; v < X.rows(); ++v) X.row(v) += offset.row(s.component(v));
  return X;
}

Eigen::MatrixXd NonlinearBlender::blend(const std::vector<const DecomposedFrame*>& frames,
                                        const std::vector<double>& weights, int threads) const {
  if (frames.empty() || frames.size() != weights.size())
    throw core::internal_error("NonlinearBlender::blend: need one weight per frame");
  double total = 0;
  for (double w : weights) {
    if (w < 0) throw core::internal_error("NonlinearBlender::blend: negative weight");
    total += w;
  }
  if (!(total > 0)) throw core::internal_error("NonlinearBlender::blend: weights must have a positive sum");
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (weights[i] > 0) used.push_back(i);

  const long m = face_count();
  std::vector<Eigen::Matrix3d> gradients(static_cast<std::size_t>(m));
  constexpr long chunk = 2048;
  core::parallel_for((m + chunk - 1) / chunk, threads, [&](long block) {
    const long end = std::min(m, (block + 1) * chunk);
    for (long k = block * chunk; k < end; ++k) {
      const auto index = static_cast<std::size_t>(k);
      geometry::RotationStretch acc{frames[used[0]]->rotations[index], frames[used[0]]->stretches[index]};
      double accumulated = weights[used[0]];
      // Iterated pairwise blending (casas2013 §3.1.2): the running blend gets weight Σ_{<i}, the next w_i.
      for (std::size_t u = 1; u < used.size(); ++u) {
        accumulated += weights[used[u]];
        const geometry::RotationStretch next{frames[used[u]]->rotations[index], frames[used[u]]->stretches[index]};
        acc = geometry::interpolate(acc, next, weights[used[u]] / accumulated);
      }
      gradients[index] = acc.matrix();
    }
  });
  Eigen::MatrixXd centroids = Eigen::MatrixXd::Zero(component_count(), 3);
  for (std::size_t i : used) centroids += (weights[i] / total) * frames[i]->component_centroids;
  return reconstruct(gradients, centroids);
}

Eigen::MatrixXd NonlinearBlender::blend_meshes(const std::vector<const Eigen::MatrixXd*>& meshes,
                                               const std::vector<double>& weights, int threads) const {
  std::vector<DecomposedFrame> decomposed;
  decomposed.reserve(meshes.size());
  for (const auto* mesh : meshes) decomposed.push_back(decompose(*mesh));
  std::vector<const DecomposedFrame*> pointers;
  for (const auto& frame : decomposed) pointers.push_back(&frame);
  return blend(pointers, weights, threads);
}

}  // namespace surfcap::blend
