#include "surfcap/geometry/rotation.hpp"

#include <Eigen/SVD>
#include <cmath>

namespace surfcap::geometry {

PolarDecomposition polar_decomposition(const Eigen::Matrix3d& A) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& W = svd.matrixV();
  Eigen::Vector3d sigma = svd.singularValues();
  // Make U·Wᵀ proper by flipping the axis of the smallest singular value (a reflection ends
  // up as a negative stretch along it).
  if ((U * W.transpose()).determinant() < 0) {
    U.col(2) = -U.col(2);
    sigma(2) = -sigma(2);
  }
  PolarDecomposition result;
  result.rotation = U * W.transpose();
  result.stretch = W * sigma.asDiagonal() * W.transpose();
  result.stretch = 0.5 * (result.stretch + result.stretch.transpose()).eval();
  return result;
}

Eigen::Quaterniond to_quaternion(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q(rotation);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return q;
}

Eigen::Matrix3d to_rotation_matrix(const Eigen::Quaterniond& rotation) {
  return rotation.normalized().toRotationMatrix();
}

Eigen::Quaterniond slerp(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t) {
  double cosine = a.coeffs().dot(b.coeffs());
  Eigen::Vector4d target = b.coeffs();
  if (cosine < 0) {  // q and −q are the same rotation: take the shorter arc
    cosine = -cosine;
    target = -target;
  }
  Eigen::Vector4d result;
  if (cosine > 1.0 - 1e-12) {
    result = a.coeffs() + t * (target - a.coeffs());
  } else {
    const double angle = std::acos(std::min(cosine, 1.0));
    const double sine = std::sin(angle);
    result = (std::sin((1 - t) * angle) / sine) * a.coeffs() + (std::sin(t * angle) / sine) * target;
  }
  Eigen::Quaterniond q;
  q.coeffs() = result.normalized();
  return q;
}

Eigen::Matrix3d lerp(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double t) { return a + t * (b - a); }

RotationStretch split_rotation_stretch(const Eigen::Matrix3d& A) {
  const PolarDecomposition polar = polar_decomposition(A);
  return {to_quaternion(polar.rotation), polar.stretch};
}

RotationStretch interpolate(const RotationStretch& a, const RotationStretch& b, double t) {
  return {slerp(a.rotation, b.rotation, t), lerp(a.stretch, b.stretch, t)};
}

Eigen::Matrix3d interpolate_transform(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double t) {
  return interpolate(split_rotation_stretch(a), split_rotation_stretch(b), t).matrix();
}

}  // namespace surfcap::geometry
