#include "surfcap/align/rigid_initialisation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <numbers>
#include <utility>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options) {
  // A subsample keeps the initialisation cheap; every k-th vertex, deterministic.
  const long step = std::max<long>(1, surface.rows() / 800);
  const long count = (surface.rows() + step - 1) / step;
  Eigen::MatrixXd points(count, 3), point_normals(count, 3);
  for (long i = 0; i < count; ++i) {
    points.row(i) = surface.row(i * step);
    point_normals.row(i) = normals.row(i * step);
  }
  const Eigen::Vector3d source_centre = points.colwise().mean().transpose();
  const Eigen::Vector3d target_centre = target.vertices().colwise().mean().transpose();
  IcpOptions icp;
  icp.max_distance = 2 * options.coarse_distance_height * model.height();
  icp.normal_compatibility = options.normal_compatibility;
  icp.iterations = 12;
  const double gate = icp.max_distance;
  auto attempt = [&](double heading) {
    RigidFit start;
    start.rotation = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix();
    start.translation = target_centre - start.rotation * source_centre;
    RigidFit fit = fit_rigid(points, point_normals, target, icp, start);
    return std::pair{fit, clamped_mean_distance(transformed(points, fit), target, gate)};
  };
  auto [best, best_score] = attempt(0.0);
  if (best_score <= 1.5 * model.mean_edge() || options.heading_samples <= 1) return best;
  for (int k = 1; k < options.heading_samples; ++k) {
    const auto [fit, score] = attempt(2 * std::numbers::pi * k / options.heading_samples);
    if (score < best_score) {
      best = fit;
      best_score = score;
    }
  }
  return best;
}

}  // namespace surfcap::align
