#include "surfcap/geometry/best_rotation.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace surfcap::geometry {

Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  correction(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * correction * svd.matrixV().transpose();
}

Eigen::Matrix4d best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  return Eigen::umeyama(from.transpose(), to.transpose(), false);
}

}  // namespace surfcap::geometry
