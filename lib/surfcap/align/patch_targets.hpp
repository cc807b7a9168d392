#pragma once
// Rigid patch targets (casas2011 §3.2): at each coarse-to-fine level every patch of the template
// is rigidly fitted to the child's reconstruction and, when enough of it found a match, its fitted
// vertices become soft targets. At the coarsest levels each patch is fitted from two more starts
// or correspondence kinds, and a model selection per patch keeps the better fit: colour-aware
// correspondences (when both meshes have colours) and the motion-predicted pose (when given).
// Only the template's observed vertices are fitted and targeted, and a fitted vertex whose closest
// reconstruction point lies on a hole's rim (observed_surface.hpp) gets no target. At the
// coarsest level a patch whose own fit lies off the reconstruction is also started from each
// fitted neighbour's motion (carried starts): a foot that turned with its shin farther than its own
// fit reaches follows the shin's fit. When asked
// (PairwiseOptions::unfold, a folded frame's second attempt), at the coarsest level a patch whose
// fit folds it onto another part of the template (stacked layers, pairwise_checks.hpp: a forearm
// laid on its upper arm where the child bends the elbow farther than the gate reaches) is searched
// for about its joints: carried by each fitted neighbour and bent about the boundary it shares
// with it, the fit taken when it lies clearly closer to the reconstruction with no fewer matches
// and unfolds the template.

#include <Eigen/Core>

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/align/target_set.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

class AlignmentTemplate;
class ObservedSurface;
struct PairwiseOptions;
struct PairwiseResult;

/// Colour-aware rigid patch matching at the coarsest `levels` levels, when both meshes have
/// colours: besides its closest-point fit, each patch is fitted with correspondences found in
/// position-colour space (nearest reconstruction vertex with `scale` metres per unit of RGB, then
/// the closest point of that vertex's faces), with vertex colours smoothed over `smoothing` rings
/// on both meshes (texture detail averaged out, part colours kept); the colour fit is taken when
/// its colour disagreement is below `gain` × the closest-point fit's.
struct PatchColorOptions {
  std::optional<double> scale = 1.0;
  int levels = 2;
  double gain = 0.8;
  int smoothing = 2;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("scale", self.scale, "Colour-aware patch matching: metres per unit of RGB in the joint space",
            Range::above(0));
    t.field("levels", self.levels, "Colour-aware matching at the coarsest N patch levels", Range::at_least(0));
    t.field("gain", self.gain,
            "Colour-aware patch fit used when its colour disagreement is below this fraction of the closest-point fit's",
            Range::above_to(0, 1));
    t.field("smoothing", self.smoothing, "Rings of vertex-colour smoothing for patch matching", Range::closed(0, 20));
  }
};

/// Motion prediction (when align_pair is given a predicted surface): at the coarsest `levels`
/// levels each patch is also fitted from its predicted pose; that fit is taken when its clamped
/// mean distance to the reconstruction is below `gain` × the other fit's, with no fewer inliers.
/// The same gain decides whether a hinged start of a folded patch lies clearly closer.
struct PredictionOptions {
  int levels = 1;
  double gain = 0.8;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("levels", self.levels, "Patch levels that also try the motion-predicted start", core::Range::at_least(0));
    t.field("gain", self.gain,
            "Predicted (or a folded patch's hinged) fit used when its mean distance is below this fraction of the "
            "other fit's",
            core::Range::above_to(0, 1));
  }
};

class PatchTargets {
 public:
  /// `target_colors` (per target vertex, 0..1; may be null) enable the colour-aware fits when the
  /// template has colours too.
  PatchTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target, const ObservedSurface& observed,
               const Eigen::MatrixXd* target_colors, const PairwiseOptions& options);
  ~PatchTargets();
  PatchTargets(const PatchTargets&) = delete;
  PatchTargets& operator=(const PatchTargets&) = delete;

  /// The reconstruction's smoothed vertex colours of the colour-aware fits; null without them.
  const Eigen::MatrixXd* smoothed_target_colors() const { return colored_ ? &target_smoothed_colors_ : nullptr; }

  /// The ICP settings of patch level `level`: the gate halves per level down to the dense gate.
  IcpOptions icp(std::size_t level) const;

  /// Fits the patches of `level` from the current `surface` (and `predicted`, the motion-predicted
  /// surface, or null) and sets the targets of the accepted ones; counts go to `result`.
  void add(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd* predicted, TargetSet& targets,
           PairwiseResult& result) const;

 private:
  struct LevelFits;
  /// Counts the stacked vertices, per patch, of the template placed by `level_fits`.
  void count_stacked(std::size_t level, const Eigen::MatrixXd& surface, LevelFits& level_fits) const;
  /// The hinge search for the patches folded onto another part (at least kFoldedShare of their
  /// vertices stacked): starts at each neighbour's fit bent about their joint by ±45°, ±90°,
  /// ±135° about kHingeAxes axes across the patch's bone, ranked with short fits of a sparse
  /// sample, the best kHingeFinalists fitted on.
  void unfold(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals, const IcpOptions& icp,
              LevelFits& level_fits, PairwiseResult& result) const;
  /// Per patch of a level, its vertices on the boundary with each neighbouring patch (the joints).
  using PatchJoints = std::map<int, std::vector<int>>;
  std::vector<PatchJoints> patch_joints(std::size_t level) const;
  /// The carried starts of the coarsest level: a patch whose own fit lies off the reconstruction
  /// (its mean compatible distance beyond the dense gate) is also fitted from each accepted
  /// neighbour's fit; a start that lies clearly closer (the prediction gain) with no fewer matches
  /// is taken. A foot or forearm that turned with its limb farther than its own fit reaches follows
  /// the limb's fit.
  void carry(std::size_t level, const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals, const IcpOptions& icp,
             LevelFits& level_fits, PairwiseResult& result) const;
  /// Patches under this many fitted vertices, and joints under kMinimumJoint boundary vertices,
  /// are not searched from a neighbour.
  static constexpr std::size_t kMinimumJointPatch = 8;
  static constexpr std::size_t kMinimumJoint = 3;
  static constexpr double kFoldedShare = 0.01;
  static constexpr int kHingeAxes = 4;
  static constexpr int kHingeSample = 64;
  static constexpr int kHingeScreeningIterations = 3;
  static constexpr std::size_t kHingeFinalists = 3;
  static constexpr int kHingePasses = 2;

  /// The fit of one patch: closest points, then the colour-aware and predicted alternatives.
  RigidFit fit_patch(std::size_t level, const std::vector<int>& members, const Eigen::MatrixXd& surface,
                     const Eigen::MatrixXd& normals, const Eigen::MatrixXd* predicted, const IcpOptions& icp,
                     PairwiseResult& result) const;

  const AlignmentTemplate& model_;
  const geometry::SurfaceQuery& target_;
  const ObservedSurface& observed_;
  const PairwiseOptions& options_;
  Eigen::MatrixXd target_smoothed_colors_;
  std::unique_ptr<ColoredTarget> colored_;  ///< null: no colour-aware fits
  /// The coarsest level's joints (patch_joints(0)), for the carried starts and the hinge search of
  /// every coarsest pass.
  std::vector<PatchJoints> coarsest_joints_;
};

}  // namespace surfcap::align
