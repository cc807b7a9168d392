#include "surfcap/align/rigid_icp.hpp"

#include <Eigen/Dense>

namespace surfcap::align {

bool compatible_closest_point(const geometry::SurfaceQuery& target, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& normal, double max_distance, double normal_compatibility,
                              geometry::SurfacePoint& closest) {
  closest = target.closest_point(point);
  if (closest.distance > max_distance) return false;
  return target.face_normal(closest.face).dot(normal) >= normal_compatibility;
}

RigidFit fit_rigid(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const geometry::SurfaceQuery& target,
                   const IcpOptions& options, const RigidFit& initial) {
  RigidFit fit = initial;
  const long k = points.rows();
  if (k == 0) return fit;
  const Eigen::Vector3d centre = points.colwise().mean().transpose();
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    long inliers = 0;
    double distance_sum = 0;
    const Eigen::Vector3d moved_centre = fit.apply(centre);
    for (long i = 0; i < k; ++i) {
      const Eigen::Vector3d p = fit.apply(points.row(i).transpose());
      const Eigen::Vector3d n = fit.rotation * normals.row(i).transpose();
      geometry::SurfacePoint closest;
      if (!compatible_closest_point(target, p, n, options.max_distance, options.normal_compatibility, closest)) continue;
      ++inliers;
      distance_sum += closest.distance;
      const Eigen::Vector3d q = closest.position;
      const Eigen::Vector3d m = target.face_normal(closest.face);
      const Eigen::Vector3d s = p - moved_centre;  // rotate about the centroid: better conditioned
      // Point-to-plane row: [s×m, m]·[ω, t] = −m·(p − q).
      Eigen::Matrix<double, 6, 1> row;
      row << s.cross(m), m;
      normal_matrix += row * row.transpose();
      rhs -= row * m.dot(p - q);
      // Point-to-point rows: [−[s]×, I]·[ω, t] = −(p − q).
      Eigen::Matrix<double, 3, 6> block;
      block << 0, s.z(), -s.y(), 1, 0, 0,  //
          -s.z(), 0, s.x(), 0, 1, 0,       //
          s.y(), -s.x(), 0, 0, 0, 1;
      normal_matrix += options.point_to_point_weight * block.transpose() * block;
      rhs -= options.point_to_point_weight * block.transpose() * (p - q);
    }
    fit.inliers = inliers;
    fit.mean_distance = inliers > 0 ? distance_sum / static_cast<double>(inliers) : 0.0;
    if (inliers < 6) break;
    const Eigen::Matrix<double, 6, 1> step = normal_matrix.ldlt().solve(rhs);
    if (!step.allFinite()) break;
    const Eigen::Vector3d omega = step.head<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d rotation_step =
        angle > 1e-15 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    // x ↦ R_step (x − c) + c + t_step with c the moved centre.
    fit.rotation = rotation_step * fit.rotation;
    fit.translation = rotation_step * (fit.translation - moved_centre) + moved_centre + step.tail<3>();
    if (angle < 1e-7 && step.tail<3>().norm() < 1e-7) break;
  }
  return fit;
}

}  // namespace surfcap::align
