#pragma once
// Per-triangle deformation gradients of a deformed mesh relative to a rest mesh with the same
// connectivity (Sumner & Popović 2004): a fourth vertex along the normal, scaled by
// 1/sqrt(|e1 × e2|), makes each triangle's affine map a full-rank 3×3 matrix T with
// T·[e1 e2 n] = [e1' e2' n'].
#include <Eigen/Core>
#include <vector>

namespace surfcap::geometry {

class DeformationGradient {
 public:
  /// Precomputes the inverse rest frames. Degenerate rest triangles get identity gradients.
  DeformationGradient(const Eigen::MatrixXd& rest_V, const Eigen::MatrixXi& F);

  /// T_k for every triangle k of `deformed` (n×3, same n as the rest mesh).
  std::vector<Eigen::Matrix3d> operator()(const Eigen::MatrixXd& deformed) const;
  /// T_k of one triangle.
  Eigen::Matrix3d triangle(const Eigen::MatrixXd& deformed, long k) const;

  long face_count() const { return F_.rows(); }

 private:
  Eigen::MatrixXi F_;
  std::vector<Eigen::Matrix3d> rest_inverse_;
};

/// Convenience: DeformationGradient(rest_V, F)(deformed).
std::vector<Eigen::Matrix3d> deformation_gradients(const Eigen::MatrixXd& rest_V, const Eigen::MatrixXi& F,
                                                   const Eigen::MatrixXd& deformed);

}  // namespace surfcap::geometry
