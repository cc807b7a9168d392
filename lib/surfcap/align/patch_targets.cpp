#include "surfcap/align/patch_targets.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/pairwise_checks.hpp"

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
  if (!model.patches().empty()) coarsest_joints_ = patch_joints(0);
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

namespace {

/// Mean over `points` (unit normals `point_normals`) of the distance to their compatible closest
/// points on the target, a point without one counting as the gate: how well a rigid placement
/// lies on the reconstruction, facing the way it does.
double compatible_distance(const Eigen::MatrixXd& points, const Eigen::MatrixXd& point_normals,
                           const geometry::SurfaceQuery& target, const IcpOptions& icp) {
  double sum = 0;
  for (long i = 0; i < points.rows(); ++i) {
    geometry::SurfacePoint closest;
    sum += compatible_closest_point(target, points.row(i).transpose(), point_normals.row(i).transpose(),
                                    icp.max_distance, icp.normal_compatibility, closest)
               ? closest.distance
               : icp.max_distance;
  }
  return points.rows() > 0 ? sum / static_cast<double>(points.rows()) : icp.max_distance;
}

/// `outer` after `inner`.
RigidFit compose(const RigidFit& outer, const RigidFit& inner) {
  RigidFit c;
  c.rotation = outer.rotation * inner.rotation;
  c.translation = outer.rotation * inner.translation + outer.translation;
  return c;
}

}  // namespace

std::vector<PatchTargets::PatchJoints> PatchTargets::patch_joints(std::size_t level) const {
  const PatchSet& set = model_.patches()[level];
  std::vector<PatchJoints> joints(static_cast<std::size_t>(set.count()));
  const Eigen::MatrixXi& F = model_.mesh().F;
  const long n = static_cast<long>(set.label.size());
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a >= n || b >= n) continue;
      const int pa = set.label[static_cast<std::size_t>(a)], pb = set.label[static_cast<std::size_t>(b)];
      if (pa != pb) joints[static_cast<std::size_t>(pa)][pb].push_back(a);
    }
  for (auto& patch : joints)
    for (auto& [neighbour, vertices] : patch) {
      std::sort(vertices.begin(), vertices.end());
      vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    }
  return joints;
}

/// The fits of one level's patches and where they put the template (accepted patches moved, the
/// others where they are), with the stacked vertices of that placement counted per patch.
struct PatchTargets::LevelFits {
  std::vector<std::vector<int>> members;  ///< per patch: its vertices that are fitted
  std::vector<RigidFit> fits;
  std::vector<char> accepted;
  std::vector<long> stacked;  ///< per patch: its vertices in stacked layers of the placement
  long stacked_total = 0;
};

void PatchTargets::count_stacked(std::size_t level, const Eigen::MatrixXd& surface, LevelFits& level_fits) const {
  const PatchSet& set = model_.patches()[level];
  const long n = static_cast<long>(set.label.size());
  Eigen::MatrixXd placed = surface.topRows(n);
  for (std::size_t p = 0; p < level_fits.members.size(); ++p)
    if (level_fits.accepted[p])
      for (const int v : level_fits.members[p]) placed.row(v) = level_fits.fits[p].apply(surface.row(v).transpose()).transpose();
  const std::vector<char> stacked =
      stacked_vertices(model_.mesh().V.topRows(n), placed, model_.mesh().F,
                       options_.checks.stacked_distance_edges * model_.mean_edge(),
                       options_.checks.stacked_rest_distance_height * model_.height());
  level_fits.stacked.assign(level_fits.members.size(), 0);
  level_fits.stacked_total = 0;
  for (long v = 0; v < n; ++v)
    if (stacked[static_cast<std::size_t>(v)]) {
      ++level_fits.stacked[static_cast<std::size_t>(set.label[static_cast<std::size_t>(v)])];
      ++level_fits.stacked_total;
    }
}

void PatchTargets::unfold(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                          const IcpOptions& icp, LevelFits& level_fits, PairwiseResult& result) const {
  const int count = model_.patches()[level].count();
  const std::vector<PatchJoints>& joints = coarsest_joints_;
  IcpOptions screening = icp;
  screening.iterations = std::min(icp.iterations, kHingeScreeningIterations);
  for (int pass = 0; pass < kHingePasses; ++pass) {
    bool changed = false;
    for (int p = 0; p < count; ++p) {
      const std::vector<int>& list = level_fits.members[static_cast<std::size_t>(p)];
      if (list.size() < kMinimumJointPatch ||
          static_cast<double>(level_fits.stacked[static_cast<std::size_t>(p)]) < kFoldedShare * static_cast<double>(list.size()))
        continue;
      const Eigen::MatrixXd points = rows_of(surface, list), point_normals = rows_of(normals, list);
      const RigidFit own = level_fits.fits[static_cast<std::size_t>(p)];
      const double own_distance =
          compatible_distance(transformed(points, own), point_normals * own.rotation.transpose(), target_, icp);
      // Starts ranked on a sparse sample of the patch, the best few fitted on with all of it.
      const long step = std::max<long>(1, static_cast<long>(list.size()) / kHingeSample);
      const long sparse_count = (static_cast<long>(list.size()) + step - 1) / step;
      Eigen::MatrixXd sparse(sparse_count, 3), sparse_normals(sparse_count, 3);
      for (long i = 0; i < sparse_count; ++i) {
        sparse.row(i) = points.row(i * step);
        sparse_normals.row(i) = point_normals.row(i * step);
      }
      const Eigen::Vector3d centre = points.colwise().mean().transpose();
      std::vector<std::pair<double, RigidFit>> starts;
      for (const auto& [neighbour, joint_vertices] : joints[static_cast<std::size_t>(p)]) {
        if (!level_fits.accepted[static_cast<std::size_t>(neighbour)] || joint_vertices.size() < kMinimumJoint) continue;
        const RigidFit& carried = level_fits.fits[static_cast<std::size_t>(neighbour)];
        Eigen::Vector3d joint = Eigen::Vector3d::Zero();
        for (const int v : joint_vertices) joint += surface.row(v).transpose();
        joint /= static_cast<double>(joint_vertices.size());
        const Eigen::Vector3d bone = centre - joint;
        if (bone.norm() <= 0) continue;
        const Eigen::Vector3d along = bone.normalized(), u = along.unitOrthogonal(), w = along.cross(u);
        const Eigen::Vector3d hinge = carried.apply(joint);
        for (int k = 0; k < kHingeAxes; ++k) {
          const double phi = std::numbers::pi * k / kHingeAxes;
          const Eigen::Vector3d axis = carried.rotation * (std::cos(phi) * u + std::sin(phi) * w);
          for (const double degrees : {-135.0, -90.0, -45.0, 45.0, 90.0, 135.0}) {
            RigidFit bend;
            bend.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis).toRotationMatrix();
            bend.translation = hinge - bend.rotation * hinge;
            const RigidFit fit = fit_rigid(sparse, sparse_normals, target_, screening, compose(bend, carried));
            starts.emplace_back(
                compatible_distance(transformed(sparse, fit), sparse_normals * fit.rotation.transpose(), target_, icp), fit);
          }
        }
      }
      // Ties keep the earlier start (stable order): deterministic.
      std::stable_sort(starts.begin(), starts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      IcpOptions rest = icp;
      rest.iterations = icp.iterations - screening.iterations;
      for (std::size_t k = 0; k < std::min<std::size_t>(kHingeFinalists, starts.size()); ++k) {
        const RigidFit fit =
            rest.iterations > 0 ? fit_rigid(points, point_normals, target_, rest, starts[k].second) : starts[k].second;
        const double distance =
            compatible_distance(transformed(points, fit), point_normals * fit.rotation.transpose(), target_, icp);
        if (!(distance < options_.prediction.gain * own_distance) ||
            fit.inliers < level_fits.fits[static_cast<std::size_t>(p)].inliers)
          continue;
        // Taken only when it unfolds: fewer stacked vertices over the whole placement.
        const std::size_t at = static_cast<std::size_t>(p);
        const RigidFit previous_fit = level_fits.fits[at];
        const char previous_accepted = level_fits.accepted[at];
        const std::vector<long> previous_stacked = level_fits.stacked;
        const long previous_total = level_fits.stacked_total;
        level_fits.fits[at] = fit;
        level_fits.accepted[at] =
            static_cast<double>(fit.inliers) >= options_.min_patch_inliers * static_cast<double>(list.size());
        count_stacked(level, surface, level_fits);
        if (level_fits.stacked_total >= previous_total) {
          level_fits.fits[at] = previous_fit;
          level_fits.accepted[at] = previous_accepted;
          level_fits.stacked = previous_stacked;
          level_fits.stacked_total = previous_total;
          continue;
        }
        if (!previous_accepted && level_fits.accepted[at]) ++result.accepted_patches;
        ++result.hinged_patches;
        changed = true;
        break;
      }
    }
    if (!changed) break;
  }
}

void PatchTargets::carry(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                         const IcpOptions& icp, LevelFits& level_fits, PairwiseResult& result) const {
  const std::vector<PatchJoints>& joints = coarsest_joints_;
  // Every start is a neighbour's own fit, not one already carried: the result does not depend on
  // the order of the patches.
  const std::vector<RigidFit> own_fits = level_fits.fits;
  const std::vector<char> own_accepted = level_fits.accepted;
  const double off_surface = options_.dense_distance_edges * model_.mean_edge();
  for (std::size_t p = 0; p < joints.size(); ++p) {
    const std::vector<int>& list = level_fits.members[p];
    if (list.size() < kMinimumJointPatch) continue;
    const Eigen::MatrixXd points = rows_of(surface, list), point_normals = rows_of(normals, list);
    const RigidFit& own = own_fits[p];
    double best = compatible_distance(transformed(points, own), point_normals * own.rotation.transpose(), target_, icp);
    if (best <= off_surface) continue;
    bool carried = false;
    for (const auto& [neighbour, joint_vertices] : joints[p]) {
      if (!own_accepted[static_cast<std::size_t>(neighbour)] || joint_vertices.size() < kMinimumJoint) continue;
      const RigidFit fit = fit_rigid(points, point_normals, target_, icp, own_fits[static_cast<std::size_t>(neighbour)]);
      const double distance =
          compatible_distance(transformed(points, fit), point_normals * fit.rotation.transpose(), target_, icp);
      if (!(distance < options_.prediction.gain * best) || fit.inliers < level_fits.fits[p].inliers) continue;
      best = distance;
      if (!level_fits.accepted[p] &&
          static_cast<double>(fit.inliers) >= options_.min_patch_inliers * static_cast<double>(list.size()))
        ++result.accepted_patches;
      level_fits.fits[p] = fit;
      level_fits.accepted[p] =
          static_cast<double>(fit.inliers) >= options_.min_patch_inliers * static_cast<double>(list.size());
      carried = true;
    }
    if (carried) ++result.carried_patches;
  }
}

void PatchTargets::add(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd* predicted,
                       TargetSet& targets, PairwiseResult& result) const {
  const Eigen::MatrixXd normals = core::vertex_normals(surface, model_.mesh().F);
  const IcpOptions settings = icp(level);
  const PatchSet& set = model_.patches()[level];
  LevelFits level_fits;
  level_fits.members.resize(static_cast<std::size_t>(set.count()));
  level_fits.fits.resize(level_fits.members.size());
  level_fits.accepted.assign(level_fits.members.size(), 0);
  for (std::size_t p = 0; p < level_fits.members.size(); ++p) {
    std::vector<int>& list = level_fits.members[p];
    for (const int v : set.vertices[p])
      if (!model_.closed_by_fill() || model_.observed_vertex(v)) list.push_back(v);
    ++result.total_patches;
    if (list.empty()) continue;
    level_fits.fits[p] = fit_patch(level, list, surface, normals, predicted, settings, result);
    level_fits.accepted[p] =
        static_cast<double>(level_fits.fits[p].inliers) >= options_.min_patch_inliers * static_cast<double>(list.size());
    if (level_fits.accepted[p]) ++result.accepted_patches;
  }
  if (level == 0) carry(level, surface, normals, settings, level_fits, result);
  if (level == 0 && options_.unfold) {
    count_stacked(level, surface, level_fits);
    if (level_fits.stacked_total > 0) unfold(level, surface, normals, settings, level_fits, result);
  }
  for (std::size_t p = 0; p < level_fits.members.size(); ++p) {
    if (!level_fits.accepted[p]) continue;
    for (const int v : level_fits.members[p]) {
      const Eigen::Vector3d goal = level_fits.fits[p].apply(surface.row(v).transpose());
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
