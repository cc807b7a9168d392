#include "surfcap/align/rigid_initialisation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <numbers>
#include <utility>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

namespace {

/// Mean over the observed target vertices.
Eigen::Vector3d observed_centre(const geometry::SurfaceQuery& target, const ObservedSurface& observed) {
  if (!observed.partial()) return target.vertices().colwise().mean().transpose();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  long count = 0;
  for (long i = 0; i < target.vertices().rows(); ++i)
    if (observed.observed_vertex(i)) {
      sum += target.vertices().row(i).transpose();
      ++count;
    }
  return count > 0 ? Eigen::Vector3d(sum / static_cast<double>(count))
                   : Eigen::Vector3d(target.vertices().colwise().mean().transpose());
}

/// clamped_mean_distance, where a closest point that is not observed counts as unmatched (gate).
double observed_mean_distance(const Eigen::MatrixXd& points, const geometry::SurfaceQuery& target,
                              const ObservedSurface& observed, double gate) {
  if (!observed.partial()) return clamped_mean_distance(points, target, gate);
  double sum = 0;
  for (long i = 0; i < points.rows(); ++i) {
    const auto closest = target.closest_point_within(points.row(i).transpose(), gate);
    sum += closest && observed.observed(*closest) ? std::min(gate, closest->distance) : gate;
  }
  return points.rows() > 0 ? sum / static_cast<double>(points.rows()) : 0.0;
}

}  // namespace

RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const ObservedSurface& observed,
                              const AlignmentTemplate& model, const PairwiseOptions& options) {
  // A subsample of the observed vertices keeps the initialisation cheap; every k-th, deterministic.
  std::vector<long> rows;
  for (long v = 0; v < surface.rows(); ++v)
    if (model.observed_vertex(v)) rows.push_back(v);
  const long step = std::max<long>(1, static_cast<long>(rows.size()) / 800);
  const long count = (static_cast<long>(rows.size()) + step - 1) / step;
  Eigen::MatrixXd points(count, 3), point_normals(count, 3);
  for (long i = 0; i < count; ++i) {
    points.row(i) = surface.row(rows[static_cast<std::size_t>(i * step)]);
    point_normals.row(i) = normals.row(rows[static_cast<std::size_t>(i * step)]);
  }
  const Eigen::Vector3d source_centre = points.colwise().mean().transpose();
  const Eigen::Vector3d target_centre = observed_centre(target, observed);
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
    return std::pair{fit, observed_mean_distance(transformed(points, fit), target, observed, gate)};
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
