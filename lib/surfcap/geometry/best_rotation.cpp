#include "surfcap/geometry/best_rotation.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <cmath>
#include <optional>

namespace surfcap::geometry {

Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  correction(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * correction * svd.matrixV().transpose();
}

namespace {

/// Unit vector orthogonal to the span of the columns of `M` when they span a plane (the largest
/// cross product of two columns); nullopt when they span less.
std::optional<Eigen::Vector3d> plane_normal(const Eigen::Matrix3d& M) {
  const Eigen::Vector3d crosses[3] = {M.col(1).cross(M.col(2)), M.col(2).cross(M.col(0)), M.col(0).cross(M.col(1))};
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (crosses[k].squaredNorm() > crosses[best].squaredNorm()) best = k;
  const double length = crosses[best].norm();
  if (!(length > 1e-6 * M.squaredNorm())) return std::nullopt;
  return Eigen::Vector3d(crosses[best] / length);
}

}  // namespace

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& covariance) {
  // argmax tr(QᵀM) over rotations is U diag(1, 1, det UVᵀ) Vᵀ (M = USVᵀ): M's orthogonal polar
  // factor when det M > 0. Newton on X ← (γX + X⁻ᵀ/γ)/2 (γ: Higham's Frobenius-norm scaling)
  // converges quadratically from X = M. A covariance of rank 2 (a thin-shell element: both
  // gradients lie in their triangle's plane) has the same U and V as M ± n_u n_vᵀ (n_u, n_v its
  // left and right null vectors), whose polar factor is that rotation for the sign giving det > 0.
  // Anything else (a reflection, rank 1, a tiny third singular value) goes to the SVD.
  const double norm = covariance.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return best_rotation(covariance);
  Eigen::Matrix3d X = covariance / norm;
  const double det = X.determinant();
  if (std::abs(det) <= 1e-12) {
    const auto left = plane_normal(X), right = plane_normal(X.transpose());
    if (!left || !right) return best_rotation(covariance);
    const Eigen::Matrix3d null = *left * right->transpose() * std::sqrt(0.5);
    X += null;
    if (X.determinant() < 0) X -= 2 * null;
    if (X.determinant() <= 1e-3) return best_rotation(covariance);
  } else if (det <= 1e-6) {
    return best_rotation(covariance);
  }
  for (int iteration = 0; iteration < 32; ++iteration) {
    // X⁻ᵀ = cofactor matrix / det.
    Eigen::Matrix3d cofactor;
    cofactor.col(0) = X.col(1).cross(X.col(2));
    cofactor.col(1) = X.col(2).cross(X.col(0));
    cofactor.col(2) = X.col(0).cross(X.col(1));
    const Eigen::Matrix3d inverse_transpose = cofactor / X.col(0).dot(cofactor.col(0));
    const double gamma = iteration < 4 ? std::sqrt(std::sqrt(inverse_transpose.squaredNorm() / X.squaredNorm())) : 1.0;
    const Eigen::Matrix3d next = 0.5 * (gamma * X + inverse_transpose / gamma);
    const double change = (next - X).squaredNorm();
    X = next;
    // Quadratic convergence: the error after this step is about the square of this change.
    if (change < 1e-18) return X;
  }
  return best_rotation(covariance);
}

Eigen::Matrix4d best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  return Eigen::umeyama(from.transpose(), to.transpose(), false);
}

}  // namespace surfcap::geometry
