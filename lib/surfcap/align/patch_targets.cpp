#include "surfcap/align/patch_targets.hpp"

#include <algorithm>
#include <cmath>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

namespace {

/// Mean squared colour difference between `points` (with `colors`) and the reconstruction's
/// (smoothed, interpolated) colour at their closest points; points farther than `gate` count as a
/// full disagreement (1).
double colour_disagreement(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors,
                           const geometry::SurfaceQuery& target, const Eigen::MatrixXd& target_colors, double gate) {
  double sum = 0;
  for (long i = 0; i < points.rows(); ++i) {
    const auto closest = target.closest_point_within(points.row(i).transpose(), gate);
    if (!closest || closest->face < 0 || closest->distance > gate) {
      sum += 1;
      continue;
    }
    sum += std::min(1.0, (interpolated_colour(target, target_colors, *closest) - colors.row(i)).squaredNorm());
  }
  return points.rows() > 0 ? sum / static_cast<double>(points.rows()) : 0.0;
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& matrix, const std::vector<int>& members) {
  Eigen::MatrixXd rows(static_cast<long>(members.size()), matrix.cols());
  for (std::size_t i = 0; i < members.size(); ++i) rows.row(static_cast<long>(i)) = matrix.row(members[i]);
  return rows;
}

}  // namespace

PatchTargets::PatchTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target,
                           const ObservedSurface& observed, const Eigen::MatrixXd* target_colors,
                           const PairwiseOptions& options)
    : model_(model), target_(target), observed_(observed), options_(options) {
  const PatchColorOptions& colour = options.patch_color;
  if (colour.scale && colour.levels > 0 && model.smoothed_colors().rows() == model.deformer().surface_vertex_count() &&
      target_colors != nullptr && target_colors->rows() == target.vertices().rows()) {
    target_smoothed_colors_ = smoothed_vertex_colors(target.faces(), *target_colors, colour.smoothing);
    colored_ = std::make_unique<ColoredTarget>(target.vertices(), target.faces(), target_smoothed_colors_, *colour.scale);
  }
}

PatchTargets::~PatchTargets() = default;

IcpOptions PatchTargets::icp(std::size_t level) const {
  IcpOptions icp;
  icp.iterations = options_.patch_icp_iterations;
  icp.normal_compatibility = options_.normal_compatibility;
  icp.max_distance = std::max(options_.coarse_distance_height * model_.height() / std::pow(2.0, static_cast<double>(level)),
                              options_.dense_distance_edges * model_.mean_edge());
  return icp;
}

RigidFit PatchTargets::fit_patch(std::size_t level, const std::vector<int>& members, const Eigen::MatrixXd& surface,
                                 const Eigen::MatrixXd& normals, const Eigen::MatrixXd* predicted,
                                 const IcpOptions& icp, PairwiseResult& result) const {
  const Eigen::MatrixXd points = rows_of(surface, members), point_normals = rows_of(normals, members);
  RigidFit fit = fit_rigid(points, point_normals, target_, icp);
  if (colored_ && static_cast<int>(level) < options_.patch_color.levels) {
    // The colour-aware fit replaces the closest-point fit only when the patch's colours agree
    // clearly better with the reconstruction's where it lands.
    const Eigen::MatrixXd point_colors = rows_of(model_.smoothed_colors(), members);
    const RigidFit colour_fit = fit_rigid(points, point_normals, point_colors, *colored_, icp);
    const double closest_score = colour_disagreement(transformed(points, fit), point_colors, target_,
                                                     target_smoothed_colors_, icp.max_distance);
    const double colour_score = colour_disagreement(transformed(points, colour_fit), point_colors, target_,
                                                    target_smoothed_colors_, icp.max_distance);
    if (colour_score < options_.patch_color.gain * closest_score) {
      fit = colour_fit;
      ++result.color_patches;
    }
  }
  if (predicted != nullptr && static_cast<int>(level) < options_.prediction.levels) {
    // A fit started where the motion prediction puts the patch replaces the fit from the parent's
    // pose when it lies clearly closer to the reconstruction with no fewer compatible matches: a
    // limb swinging farther in one frame than the correspondence gate is found where it went.
    const RigidFit predicted_fit =
        fit_rigid(points, point_normals, target_, icp, best_rigid_motion(points, rows_of(*predicted, members)));
    const double current_score = clamped_mean_distance(transformed(points, fit), target_, icp.max_distance);
    const double predicted_score = clamped_mean_distance(transformed(points, predicted_fit), target_, icp.max_distance);
    if (predicted_score < options_.prediction.gain * current_score && predicted_fit.inliers >= fit.inliers) {
      fit = predicted_fit;
      ++result.predicted_patches;
    }
  }
  return fit;
}

void PatchTargets::add(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd* predicted,
                       TargetSet& targets, PairwiseResult& result) const {
  const Eigen::MatrixXd normals = core::vertex_normals(surface, model_.mesh().F);
  const IcpOptions settings = icp(level);
  std::vector<int> observed_members;
  for (const auto& patch : model_.patches()[level].vertices) {
    const std::vector<int>* members = &patch;
    if (model_.closed_by_fill()) {
      observed_members.clear();
      for (const int v : patch)
        if (model_.observed_vertex(v)) observed_members.push_back(v);
      members = &observed_members;
    }
    ++result.total_patches;
    if (members->empty()) continue;
    const RigidFit fit = fit_patch(level, *members, surface, normals, predicted, settings, result);
    if (static_cast<double>(fit.inliers) < options_.min_patch_inliers * static_cast<double>(members->size())) continue;
    ++result.accepted_patches;
    for (const int v : *members) {
      const Eigen::Vector3d goal = fit.apply(surface.row(v).transpose());
      if (observed_.partial()) {
        const auto closest = target_.closest_point_within(goal, settings.max_distance);
        if (closest && !observed_.observed(*closest)) continue;
      }
      targets.positions.row(v) = goal.transpose();
      targets.weights(v) = options_.patch_weight;
      ++result.patch_constraints;
    }
  }
}

}  // namespace surfcap::align
