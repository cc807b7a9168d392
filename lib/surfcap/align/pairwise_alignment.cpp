#include "surfcap/align/pairwise_alignment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "surfcap/align/feature_constraints.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::align {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// One pairwise alignment: levels → sources → merge → solve. Each step starts from the current
/// surface, lets the sources set or merge their targets (later ones override or merge with
/// earlier ones) and solves.
class PairwiseSchedule {
 public:
  PairwiseSchedule(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                   const geometry::SurfaceQuery& target, const PairwiseOptions& options,
                   const Eigen::MatrixXd* target_colors, const FeaturePair& features, const Eigen::MatrixXd* predicted)
      : model_(model),
        target_(target),
        options_(options),
        features_(features),
        predicted_(predicted),
        surface_count_(model.deformer().surface_vertex_count()),
        positions_(parent_positions),
        observed_(target.vertices(), target.faces()),
        patches_(model, target, observed_, target_colors, options),
        dense_(model, target, observed_, target_colors, options),
        coverage_(model, target, observed_, options, features.cameras),
        creases_(model, target, observed_, options.crease, options.normal_compatibility) {
    result_.predicted = predicted != nullptr;
    result_.holes = observed_.holes();
    result_.largest_hole_perimeter = observed_.largest_hole_perimeter();
  }

  PairwiseResult run() {
    initialise();
    for (std::size_t level = 0; level < model_.patches().size(); ++level)
      for (int pass = 0; pass < (level == 0 ? options_.coarse_passes : 1); ++pass) patch_level(level);
    for (int iteration = 0; iteration < options_.dense_iterations; ++iteration)
      if (!dense_iteration()) break;
    if (use_flow())
      for (int iteration = 0; iteration < options_.flow.iterations; ++iteration)
        if (!flow_iteration()) break;
    check();
    result_.positions = std::move(positions_);
    return std::move(result_);
  }

 private:
  Eigen::MatrixXd surface() const { return positions_.topRows(surface_count_); }

  bool use_flow() const {
    return options_.flow.weight && features_.appearance != nullptr && features_.child_views != nullptr &&
           !features_.child_views->images().empty();
  }

  /// Rigid initialisation, and the feature matches between parent and child predicted by it.
  void initialise() {
    const auto start = Clock::now();
    const Eigen::MatrixXd parent_surface = surface();
    RigidColours colours;
    if (patches_.smoothed_target_colors() != nullptr)
      colours = {&model_.smoothed_colors(), patches_.smoothed_target_colors(), options_.patch_color.scale.value_or(0)};
    const RigidFit rigid = rigid_initialisation(parent_surface, core::vertex_normals(parent_surface, model_.mesh().F),
                                                target_, model_, options_, colours);
    positions_ = transformed(positions_, rigid);
    const Eigen::Vector3d forward = rigid.rotation * Eigen::Vector3d::UnitZ();
    result_.heading_change = std::atan2(forward.x(), forward.z());
    if (options_.feature.weight && features_.parent != nullptr && features_.child != nullptr) {
      FeatureMatching matching = feature_constraints(
          parent_surface, model_.mesh().F, *features_.parent, *features_.child, rigid.rotation, rigid.translation,
          options_.dense_distance_edges * model_.mean_edge(), model_.height(), options_.feature);
      feature_targets_ = std::move(matching.constraints);
      drop_unobserved(feature_targets_);
      result_.feature_constraints = static_cast<long>(feature_targets_.size());
    }
    result_.timings.matching += seconds_since(start);
  }

  /// The sources every step shares, after its own: creases (unless `creases` is false), coverage
  /// pulls within `reach`, image features.
  void add_shared(const Eigen::MatrixXd& surface, bool creases, double reach, TargetSet& targets) {
    if (creases) creases_.add(surface, targets, result_);
    coverage_.add(surface, reach, targets, result_);
    add_feature_targets(surface, model_.mesh().F, feature_targets_, options_.feature.weight.value_or(0),
                        targets.positions, targets.weights);
  }

  /// Coarse-to-fine rigid patch matching (casas2011 §3.2): the patch fits become soft constraints.
  void patch_level(std::size_t level) {
    const auto start = Clock::now();
    const Eigen::MatrixXd current = surface();
    TargetSet targets(current);
    patches_.add(level, current, predicted_, targets, result_);
    const int levels = static_cast<int>(model_.patches().size());
    add_shared(current, static_cast<int>(level) >= levels - options_.crease.patch_levels,
               patches_.icp(level).max_distance, targets);
    result_.timings.matching += seconds_since(start);
    if (targets.weights.maxCoeff() > 0) solve(targets);
  }

  /// Dense fit: every surface vertex towards its compatible closest point. False when none matched.
  bool dense_iteration() {
    const auto start = Clock::now();
    const Eigen::MatrixXd current = surface();
    TargetSet targets(current);
    const long matched = dense_.add(current, targets, result_);
    result_.dense_constraints = matched;
    add_shared(current, true, options_.coarse_distance_height * model_.height(), targets);
    result_.timings.matching += seconds_since(start);
    if (matched == 0) return false;
    solve(targets);
    return true;
  }

  /// Appearance flow after the dense fit: drift-free dense image correspondences overriding the
  /// dense targets. False when no target was set.
  bool flow_iteration() {
    const auto start = Clock::now();
    const Eigen::MatrixXd current = surface();
    TargetSet targets(current);
    result_.dense_constraints = dense_.add(current, targets, result_);
    FlowTargets flow = flow_targets(*features_.appearance, current, model_.mesh().F, *features_.child_views,
                                    model_.mean_edge(), options_.flow);
    drop_unobserved(flow);
    result_.flow_pixels = flow.pixels;
    result_.flow_vertices = set_flow_targets(flow, *options_.flow.weight, targets.positions, targets.weights);
    add_shared(current, true, options_.coarse_distance_height * model_.height(), targets);
    result_.timings.matching += seconds_since(start);
    if (targets.weights.maxCoeff() <= 0) return false;
    solve(targets);
    return true;
  }

  /// Is `point` (on or near the child's reconstruction) on its observed part?
  bool observed_target(const Eigen::Vector3d& point) const {
    return !observed_.partial() || observed_.observed(target_.closest_point(point));
  }

  /// Image feature matches on the template's closing surface or landing on a hole's rim.
  void drop_unobserved(std::vector<FeatureConstraint>& constraints) const {
    if (!observed_.partial() && !model_.closed_by_fill()) return;
    const auto unobserved = [this](const FeatureConstraint& c) {
      return !model_.observed_face(c.face) || !observed_target(c.target);
    };
    constraints.erase(std::remove_if(constraints.begin(), constraints.end(), unobserved), constraints.end());
  }

  /// Flow targets of the closing surface's vertices or landing on a hole's rim.
  void drop_unobserved(FlowTargets& flow) const {
    if (!observed_.partial() && !model_.closed_by_fill()) return;
    for (long v = 0; v < flow.support.size(); ++v)
      if (flow.support(v) > 0 && (!model_.observed_vertex(v) || !observed_target(flow.targets.row(v).transpose())))
        flow.support(v) = 0;
  }

  /// One solve towards `targets`, their weights scaled to the template's resolution
  /// (AlignmentTemplate::weight_scale).
  void solve(const TargetSet& targets) {
    auto begin = Clock::now();
    const Eigen::VectorXd weights = model_.weight_scale() * targets.weights;
    model_.deformer().factor(weights, solver_);
    result_.timings.factorisation += seconds_since(begin);
    begin = Clock::now();
    positions_ = model_.deformer().deform(solver_, positions_, targets.positions, weights, options_.rotation_iterations);
    result_.timings.solves += seconds_since(begin);
  }

  /// Residuals, the two-sided coverage, the stacked layers and the merged regions of the result
  /// (pairwise_checks.hpp).
  void check() {
    const auto start = Clock::now();
    const Eigen::MatrixXd aligned = surface();
    const Eigen::VectorXd distances = observed_distances(aligned);
    result_.mean_residual = distances.mean();
    result_.max_residual = distances.maxCoeff();
    std::vector<char> counted;  // the observed reconstruction vertices
    if (observed_.partial())
      for (long i = 0; i < target_.vertices().rows(); ++i) counted.push_back(observed_.observed_vertex(i) ? 1 : 0);
    result_.uncovered_fraction =
        uncovered_fraction(target_, aligned, model_.mesh().F, options_.checks.uncovered_distance_edges * model_.mean_edge(),
                           observed_.partial() ? &counted : nullptr, features_.cameras);
    result_.stacked_fraction = stacked_fraction(model_.mesh().V, aligned, model_.mesh().F,
                                                options_.checks.stacked_distance_edges * model_.mean_edge(),
                                                options_.checks.stacked_rest_distance_height * model_.height());
    const MergedRegions merged =
        merged_regions(model_.mesh().V, aligned, model_.mesh().F, target_, model_.mean_edge(), model_.height());
    result_.merged_regions = merged.regions;
    result_.merged_fraction = merged.fraction;
    result_.timings.matching += seconds_since(start);
  }

  /// Distances aligned vertex → reconstruction of the vertices observed in the child (all of them
  /// when none is); sets the unobserved fraction.
  Eigen::VectorXd observed_distances(const Eigen::MatrixXd& aligned) {
    if (!observed_.partial() && !model_.closed_by_fill()) return surface_distances(aligned, target_);
    std::vector<double> observed, all;
    for (long v = 0; v < aligned.rows(); ++v) {
      const geometry::SurfacePoint closest = target_.closest_point(aligned.row(v).transpose());
      all.push_back(closest.distance);
      if (model_.observed_vertex(v) && observed_.observed(closest)) observed.push_back(closest.distance);
    }
    result_.unobserved_fraction = 1.0 - static_cast<double>(observed.size()) / static_cast<double>(all.size());
    const std::vector<double>& kept = observed.empty() ? all : observed;
    return Eigen::Map<const Eigen::VectorXd>(kept.data(), static_cast<long>(kept.size()));
  }

  const AlignmentTemplate& model_;
  const geometry::SurfaceQuery& target_;
  const PairwiseOptions& options_;
  const FeaturePair& features_;
  const Eigen::MatrixXd* predicted_;
  const long surface_count_;
  Eigen::MatrixXd positions_;
  PairwiseResult result_;
  std::vector<FeatureConstraint> feature_targets_;
  geometry::SparseCholesky solver_;  ///< refactored by every solve (one symbolic analysis per pair)
  ObservedSurface observed_;  ///< of the child's reconstruction; before the sources that hold it
  PatchTargets patches_;
  DenseTargets dense_;
  CoverageTargets coverage_;
  CreaseTargets creases_;
};

}  // namespace

PairwiseResult align_pair(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                          const geometry::SurfaceQuery& target, const PairwiseOptions& options,
                          const Eigen::MatrixXd* target_colors, const FeaturePair& features,
                          const Eigen::MatrixXd* predicted_surface) {
  const VolumeDeformer& deformer = model.deformer();
  if (parent_positions.rows() != deformer.vertex_count()) throw core::internal_error("align_pair: parent size");
  if (predicted_surface != nullptr && predicted_surface->rows() != deformer.surface_vertex_count())
    throw core::internal_error("align_pair: predicted surface size");
  if (features.child_views != nullptr && &features.child_views->reconstruction() != &target)
    throw core::internal_error("align_pair: the child views are of another reconstruction");
  return PairwiseSchedule(model, parent_positions, target, options, target_colors, features, predicted_surface).run();
}

}  // namespace surfcap::align
