#include "surfcap/geometry/deformation_gradient.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace surfcap::geometry {
namespace {

/// [e1 e2 n/sqrt|n|] of triangle k (Sumner's fourth vertex).
Eigen::Matrix3d triangle_frame(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, long k) {
  const Eigen::Vector3d p0 = V.row(F(k, 0)).transpose();
  const Eigen::Vector3d e1 = V.row(F(k, 1)).transpose() - p0;
  const Eigen::Vector3d e2 = V.row(F(k, 2)).transpose() - p0;
  const Eigen::Vector3d cross = e1.cross(e2);
  const double length = cross.norm();
  Eigen::Matrix3d frame;
  frame.col(0) = e1;
  frame.col(1) = e2;
  frame.col(2) = length > 0 ? Eigen::Vector3d(cross / std::sqrt(length)) : Eigen::Vector3d::Zero();
  return frame;
}

}  // namespace

DeformationGradient::DeformationGradient(const Eigen::MatrixXd& rest_V, const Eigen::MatrixXi& F)
    : F_(F), rest_inverse_(static_cast<std::size_t>(F.rows())) {
  for (long k = 0; k < F.rows(); ++k) {
    const Eigen::Matrix3d frame = triangle_frame(rest_V, F, k);
    Eigen::Matrix3d inverse;
    bool invertible = false;
    double determinant = 0;
    frame.computeInverseAndDetWithCheck(inverse, determinant, invertible, 1e-30);
    rest_inverse_[static_cast<std::size_t>(k)] = invertible ? inverse : Eigen::Matrix3d::Zero();
  }
}

Eigen::Matrix3d DeformationGradient::triangle(const Eigen::MatrixXd& deformed, long k) const {
  const Eigen::Matrix3d& inverse = rest_inverse_[static_cast<std::size_t>(k)];
  if (inverse.isZero(0)) return Eigen::Matrix3d::Identity();
  return triangle_frame(deformed, F_, k) * inverse;
}

std::vector<Eigen::Matrix3d> DeformationGradient::operator()(const Eigen::MatrixXd& deformed) const {
  std::vector<Eigen::Matrix3d> gradients(static_cast<std::size_t>(F_.rows()));
  for (long k = 0; k < F_.rows(); ++k) gradients[static_cast<std::size_t>(k)] = triangle(deformed, k);
  return gradients;
}

std::vector<Eigen::Matrix3d> deformation_gradients(const Eigen::MatrixXd& rest_V, const Eigen::MatrixXi& F,
                                                   const Eigen::MatrixXd& deformed) {
  return DeformationGradient(rest_V, F)(deformed);
}

}  // namespace surfcap::geometry
