#include "surfcap/align/dense_targets.hpp"

#include <cmath>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/geometry/vertex_grid.hpp"

namespace surfcap::align {

DenseTargets::DenseTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target,
                           const ObservedSurface& observed, const Eigen::MatrixXd* target_colors,
                           const PairwiseOptions& options)
    : model_(model),
      target_(target),
      observed_(observed),
      target_colors_(target_colors),
      options_(options),
      gate_(options.dense_distance_edges * model.mean_edge()),
      color_radius_(options.color.radius_edges * model.mean_edge()) {
  if (options.color.sigma && target_colors != nullptr && model.mesh().has_colors() &&
      target_colors->rows() == target.vertices().rows())
    grid_ = std::make_unique<geometry::VertexGrid>(target.vertices(), color_radius_);
}

DenseTargets::~DenseTargets() = default;

std::optional<Eigen::Vector3d> DenseTargets::colour_target(long v, const Eigen::Vector3d& closest,
                                                           const Eigen::Vector3d& normal) const {
  // Target vertices near the closest point, weighted by colour agreement and distance.
  const Eigen::Vector3d colour = model_.mesh().colors.row(v).transpose();
  const double radius2 = color_radius_ * color_radius_;
  const double sigma = *options_.color.sigma;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight_sum = 0;
  grid_->around(closest, [&](long j) {
    const Eigen::Vector3d x = target_.vertices().row(j).transpose();
    const double d2 = (x - closest).squaredNorm();
    if (d2 > radius2) return;
    const double c2 = (target_colors_->row(j).transpose() - colour).squaredNorm();
    const double w = std::exp(-c2 / (2 * sigma * sigma) - d2 / (2 * radius2 / 4));
    sum += w * x;
    weight_sum += w;
  });
  if (weight_sum <= 1e-6) return std::nullopt;
  const geometry::SurfacePoint projected = target_.closest_point(sum / weight_sum);
  if (target_.face_normal(projected.face).dot(normal) < options_.normal_compatibility || !observed_.observed(projected))
    return std::nullopt;
  return projected.position;
}

long DenseTargets::add(const Eigen::MatrixXd& surface, TargetSet& targets, PairwiseResult& result) const {
  const Eigen::MatrixXd normals = core::vertex_normals(surface, model_.mesh().F);
  long matched = 0;
  result.color_constraints = 0;
  for (long v = 0; v < model_.deformer().surface_vertex_count(); ++v) {
    geometry::SurfacePoint closest;
    if (!model_.observed_vertex(v) ||
        !compatible_closest_point(target_, surface.row(v).transpose(), normals.row(v).transpose(), gate_,
                                  options_.normal_compatibility, closest) ||
        !observed_.observed(closest))
      continue;
    Eigen::Vector3d goal = closest.position;
    if (grid_) {
      if (const auto moved = colour_target(v, closest.position, normals.row(v).transpose())) {
        goal = *moved;
        ++result.color_constraints;
      }
    }
    targets.positions.row(v) = goal.transpose();
    targets.weights(v) = options_.dense_weight;
    ++matched;
  }
  return matched;
}

}  // namespace surfcap::align
