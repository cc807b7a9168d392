#pragma once
// Rotations for non-linear blending (casas2013 eqs. 1–2): polar decomposition A = R·S,
// quaternion conversion, shortest-arc slerp and linear interpolation of scale/shear.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace surfcap::geometry {

/// A = rotation · stretch with rotation proper (det +1) and stretch symmetric. For det A > 0 the
/// stretch is positive definite; for a reflection (det A < 0) the stretch takes the sign.
struct PolarDecomposition {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
};
PolarDecomposition polar_decomposition(const Eigen::Matrix3d& A);

/// Unit quaternion of a rotation matrix (w ≥ 0), and back.
Eigen::Quaterniond to_quaternion(const Eigen::Matrix3d& rotation);
Eigen::Matrix3d to_rotation_matrix(const Eigen::Quaterniond& rotation);

/// Spherical interpolation along the shortest arc: t = 0 gives a, t = 1 gives ±b (same rotation).
Eigen::Quaterniond slerp(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t);

/// S_a + t (S_b − S_a) (casas2013 eq. 2).
Eigen::Matrix3d lerp(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double t);

/// A transform split for blending: rotation as a quaternion, scale/shear as a symmetric matrix.
struct RotationStretch {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d matrix() const { return to_rotation_matrix(rotation) * stretch; }
};
RotationStretch split_rotation_stretch(const Eigen::Matrix3d& A);

/// casas2013 eqs. 1–2: slerp of the rotations, lerp of the stretches, weight t of b.
RotationStretch interpolate(const RotationStretch& a, const RotationStretch& b, double t);

/// interpolate() on plain matrices (decomposes both).
Eigen::Matrix3d interpolate_transform(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double t);

}  // namespace surfcap::geometry
