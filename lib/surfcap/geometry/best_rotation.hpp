#pragma once
// Best-fit rigid motions of paired point sets (Kabsch / Umeyama), for rigid patch fits, posing a
// volume onto a surface and the per-element rotations of the deformation model.

#include <Eigen/Core>

namespace surfcap::geometry {

/// argmin over rotations Q of ‖A Q − B‖ given the covariance M = AᵀB (A, B rows paired, centred
/// when a translation is fitted too): Kabsch, reflections excluded.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance);

/// The rigid motion (4×4, no scaling) best taking the rows of `from` onto the rows of `to`
/// (Umeyama).
Eigen::Matrix4d best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to);

}  // namespace surfcap::geometry
