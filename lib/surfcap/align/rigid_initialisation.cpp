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
                              const PairwiseOptions& options, const RigidColours& colours) {
  // A subsample keeps the initialisation cheap; every k-th vertex, deterministic.
  const long step = std::max<long>(1, surface.rows() / 800);
  const long count = (surface.rows() + step - 1) / step;
  const bool coloured = colours.surface != nullptr && colours.target != nullptr && colours.scale > 0 &&
                        colours.surface->rows() == surface.rows() && colours.target->rows() == target.vertices().rows();
  Eigen::MatrixXd points(count, 3), point_normals(count, 3), point_colours(coloured ? count : 0, 3);
  for (long i = 0; i < count; ++i) {
    points.row(i) = surface.row(i * step);
    point_normals.row(i) = normals.row(i * step);
    if (coloured) point_colours.row(i) = colours.surface->row(i * step);
  }
  const Eigen::Vector3d source_centre = points.colwise().mean().transpose();
  const Eigen::Vector3d target_centre = target.vertices().colwise().mean().transpose();
  IcpOptions icp;
  icp.max_distance = 2 * options.coarse_distance_height * model.height();
  icp.normal_compatibility = options.normal_compatibility;
  icp.iterations = 12;
  const double gate = icp.max_distance;
  auto fit_from = [&](double heading) {
    RigidFit start;
    start.rotation = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix();
    start.translation = target_centre - start.rotation * source_centre;
    return fit_rigid(points, point_normals, target, icp, start);
  };
  auto score = [&](const RigidFit& fit) {
    const Eigen::MatrixXd moved = transformed(points, fit);
    return coloured ? clamped_mean_joint_distance(moved, point_colours, target, *colours.target, colours.scale, gate)
                    : clamped_mean_distance(moved, target, gate);
  };
  auto attempt = [&](double heading) {
    const RigidFit fit = fit_from(heading);
    return std::pair{fit, score(fit)};
  };
  // Frames that overlap as they stand keep their heading; only a search compares headings.
  RigidFit best = fit_from(0.0);
  if (clamped_mean_distance(transformed(points, best), target, gate) <= 1.5 * model.mean_edge() ||
      options.heading_samples <= 1)
    return best;
  double best_score = score(best);
  for (int k = 1; k < options.heading_samples; ++k) {
    const auto [fit, fit_score] = attempt(2 * std::numbers::pi * k / options.heading_samples);
    if (fit_score < best_score) {
      best = fit;
      best_score = fit_score;
    }
  }
  return best;
}

}  // namespace surfcap::align
