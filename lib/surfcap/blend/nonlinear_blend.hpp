#pragma once
// Exact non-linear blend b(M, w) (casas2013 §3.1.2, eqs. 1–2): per-triangle deformation
// gradients relative to the template, split into rotation (quaternion, slerp) and scale/shear
// (lerp), iterated pairwise for N > 2, then Poisson reconstruction Gᵀ A G x = Gᵀ A g with a
// solver factored once per template. One vertex per connected component is pinned and each
// component is then moved so its centroid is the linear blend of the source centroids.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::blend {

/// One source frame prepared for blending: per-triangle rotation/stretch and per-component
/// vertex centroids. Computing it is the costly part (a polar decomposition per triangle), so
/// motion spaces prepare every source frame once and blend it many times.
struct DecomposedFrame {
  std::vector<Eigen::Quaterniond> rotations;  ///< per triangle
  std::vector<Eigen::Matrix3d> stretches;     ///< per triangle, symmetric
  Eigen::MatrixXd component_centroids;        ///< components×3
};

class NonlinearBlender {
 public:
  /// Builds G, A and factors Gᵀ A G (+ one pinned vertex per connected component).
  explicit NonlinearBlender(const core::Mesh& template_mesh);
  ~NonlinearBlender();
  NonlinearBlender(NonlinearBlender&&) noexcept;
  NonlinearBlender& operator=(NonlinearBlender&&) noexcept;

  /// Deformation gradients of `positions` (n×3) relative to the template, decomposed.
  DecomposedFrame decompose(const Eigen::MatrixXd& positions) const;

  /// b(M, w): weights ≥ 0 with a positive sum (normalised here); `threads` for the per-triangle
  /// loop (results do not depend on it).
  Eigen::MatrixXd blend(const std::vector<const DecomposedFrame*>& frames, const std::vector<double>& weights,
                        int threads = 1) const;
  /// Convenience: decomposes `meshes` then blends.
  Eigen::MatrixXd blend_meshes(const std::vector<const Eigen::MatrixXd*>& meshes, const std::vector<double>& weights,
                               int threads = 1) const;

  /// Poisson reconstruction of per-triangle target gradients (the 3×3 maps of the template's
  /// triangles), with each component's centroid placed at `component_centroids`.
  Eigen::MatrixXd reconstruct(const std::vector<Eigen::Matrix3d>& gradients,
                              const Eigen::MatrixXd& component_centroids) const;

  long vertex_count() const;
  long face_count() const;
  int component_count() const;
  /// Connected component of each vertex (0-based, in order of first vertex).
  const Eigen::VectorXi& vertex_components() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace surfcap::blend
