#include "surfcap/align/rigid_initialisation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <numbers>
#include <utility>
#include <vector>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

namespace {

/// Every `step`-th row of a surface's points, normals and (when given) colours.
struct PointSample {
  Eigen::MatrixXd points, normals, colours;
  PointSample(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& surface_normals, const Eigen::MatrixXd* surface_colours,
              long step) {
    const long count = (surface.rows() + step - 1) / step;
    points.resize(count, 3);
    normals.resize(count, 3);
    colours.resize(surface_colours != nullptr ? count : 0, 3);
    for (long i = 0; i < count; ++i) {
      points.row(i) = surface.row(i * step);
      normals.row(i) = surface_normals.row(i * step);
      if (surface_colours != nullptr) colours.row(i) = surface_colours->row(i * step);
    }
  }
};

}  // namespace

RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options, const RigidColours& colours) {
  const bool coloured = colours.surface != nullptr && colours.target != nullptr && colours.scale > 0 &&
                        colours.surface->rows() == surface.rows() && colours.target->rows() == target.vertices().rows();
  // A subsample keeps the initialisation cheap (every k-th vertex, deterministic); a sparser one of
  // it ranks the headings of a search.
  const PointSample sample(surface, normals, coloured ? colours.surface : nullptr,
                           std::max<long>(1, surface.rows() / 800));
  const PointSample sparse(sample.points, sample.normals, coloured ? &sample.colours : nullptr, 4);
  const Eigen::MatrixXd& points = sample.points;
  const Eigen::MatrixXd& point_normals = sample.normals;
  const Eigen::Vector3d source_centre = points.colwise().mean().transpose();
  const Eigen::Vector3d target_centre = target.vertices().colwise().mean().transpose();
  IcpOptions icp;
  icp.max_distance = 2 * options.coarse_distance_height * model.height();
  icp.normal_compatibility = options.normal_compatibility;
  icp.iterations = 12;
  // The body is not rigid: a limb that swung away from where the parent held it pulls a fit of
  // every point round the vertical (from one stride to the other a walker's legs trade places, and
  // turning the whole body lays each leg on the other). The closest half of the points — the trunk
  // that moved least — sets the rigid motion; the limbs are the patches' to find. Asked to
  // (PairwiseOptions::whole_body_start, a frame still folded after the joint search) it fits every
  // point instead: the whole-body fit turns the body part of the way towards a long limb folded
  // as a whole, and the joint search starts from there.
  icp.trim_fraction = options.whole_body_start ? 1.0 : 0.5;
  const double gate = icp.max_distance;
  auto start_at = [&](double heading) {
    RigidFit start;
    start.rotation = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix();
    start.translation = target_centre - start.rotation * source_centre;
    return start;
  };
  auto score_of = [&](const PointSample& of, const RigidFit& fit) {
    const double fraction = icp.trim_fraction;
    const Eigen::MatrixXd moved = transformed(of.points, fit);
    return coloured
               ? clamped_mean_joint_distance(moved, of.colours, target, *colours.target, colours.scale, gate, fraction)
               : clamped_mean_distance(moved, target, gate, fraction);
  };
  auto score = [&](const RigidFit& fit) { return score_of(sample, fit); };
  // Scores, like the fits, are over the closest half of the points: the trunk's fit, in shape and,
  // with colours, in colour (a body turned half round shows its back where the front was). A
  // whole-body score would prefer the body turned to lay each leg on the other.
  // Frames whose trunks overlap as they stand keep their heading; only a search compares headings.
  RigidFit best = fit_rigid(points, point_normals, target, icp, start_at(0.0));
  if (score(best) <= 1.5 * model.mean_edge() ||
      options.heading_samples <= 1)
    return best;
  // Coarse to fine: every other heading is fitted to the sparse sample with a few iterations and
  // scored on it; the best few are fitted on with the whole sample (the ICP continues from where it
  // stopped) and compared with heading 0's fit.
  constexpr int screening_iterations = 4;
  constexpr std::size_t finalists = 3;
  IcpOptions screening = icp;
  screening.iterations = std::min(icp.iterations, screening_iterations);
  std::vector<std::pair<double, RigidFit>> screened;
  for (int k = 1; k < options.heading_samples; ++k) {
    const RigidFit fit = fit_rigid(sparse.points, sparse.normals, target, screening,
                                   start_at(2 * std::numbers::pi * k / options.heading_samples));
    screened.emplace_back(score_of(sparse, fit), fit);
  }
  // Ties keep the lower heading (stable order): deterministic.
  std::stable_sort(screened.begin(), screened.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  IcpOptions rest = icp;
  rest.iterations = icp.iterations - screening.iterations;
  double best_score = score(best);
  for (std::size_t k = 0; k < std::min(finalists, screened.size()); ++k) {
    const RigidFit fit = rest.iterations > 0 ? fit_rigid(points, point_normals, target, rest, screened[k].second)
                                             : screened[k].second;
    const double fit_score = score(fit);
    if (fit_score < best_score) {
      best = fit;
      best_score = fit_score;
    }
  }
  return best;
}

}  // namespace surfcap::align
