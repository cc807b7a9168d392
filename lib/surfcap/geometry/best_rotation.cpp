#include "surfcap/geometry/best_rotation.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

namespace surfcap::geometry {

namespace {

/// Kabsch through the singular value decomposition: U·diag(1, 1, det(UVᵀ))·Vᵀ.
Eigen::Matrix3d rotation_by_svd(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  correction(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * correction * svd.matrixV().transpose();
}

/// The cofactor matrix det(M)·M⁻ᵀ (defined for singular M too): columns are cross products.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& M) {
  Eigen::Matrix3d C;
  C.col(0) = M.col(1).cross(M.col(2));
  C.col(1) = M.col(2).cross(M.col(0));
  C.col(2) = M.col(0).cross(M.col(1));
  return C;
}

/// The orthogonal polar factor of M (det M > 0) by Newton's iteration X ← (γX + (γX)⁻ᵀ)/2 with
/// Higham's Frobenius-norm scaling γ; false if it does not converge.
bool orthogonal_polar_factor(const Eigen::Matrix3d& M, Eigen::Matrix3d& X) {
  X = M;
  bool scaled = true;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const Eigen::Matrix3d C = cofactor(X);
    const double det = X.col(0).dot(C.col(0));
    if (!(det > 0) || !std::isfinite(det)) return false;
    const Eigen::Matrix3d inverse_transpose = C / det;
    double gamma = 1;
    if (scaled) gamma = std::sqrt(std::sqrt(inverse_transpose.squaredNorm() / X.squaredNorm()));
    const Eigen::Matrix3d next = 0.5 * (gamma * X + inverse_transpose / gamma);
    const double change = (next - X).squaredNorm();
    X = next;
    if (change < 1e-4) scaled = false;  // near the fixed point the unscaled step converges quadratically
    // A step of ‖ΔX‖ leaves an error of about ‖ΔX‖²/2: below 10⁻⁹ that is beneath double precision.
    if (change < 1e-18) return true;
  }
  return false;
}

}  // namespace

Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance) {
  // Kabsch's rotation U·diag(1, 1, det(UVᵀ))·Vᵀ (M = UΣVᵀ) without the SVD where it is cheap to
  // get otherwise: for det M clearly positive it is M's orthogonal polar factor; for a rank-2 M
  // (a flat element: its rest gradients span a plane) it is the polar factor of
  // M + c·cof(M), which shares U and V and whose third singular value is c·σ₁σ₂·det(UVᵀ) — the
  // sign Kabsch's correction gives. Everything else (reflections, near rank 1) takes the SVD.
  const Eigen::Matrix3d& M = covariance;
  const double norm2 = M.squaredNorm();
  if (!(norm2 > 0) || !std::isfinite(norm2)) return rotation_by_svd(M);
  const double norm3 = norm2 * std::sqrt(norm2);
  const Eigen::Matrix3d C = cofactor(M);
  const double det = M.col(0).dot(C.col(0));
  Eigen::Matrix3d R;
  if (det > 1e-6 * norm3) {
    if (orthogonal_polar_factor(M, R)) return R;
  } else if (std::abs(det) < 1e-12 * norm3 && C.squaredNorm() > 1e-12 * norm2 * norm2) {
    if (orthogonal_polar_factor(M + std::sqrt(norm2 / C.squaredNorm()) * C, R)) return R;
  }
  return rotation_by_svd(M);
}

Eigen::Matrix4d best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  return Eigen::umeyama(from.transpose(), to.transpose(), false);
}

}  // namespace surfcap::geometry
