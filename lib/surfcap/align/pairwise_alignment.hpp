#pragma once
// Pairwise non-rigid alignment (casas2011 §3.2): the template, already aligned to a parent frame,
// deformed onto a child frame's reconstruction. A rigid initialisation, then a schedule of solves
// of the volumetric Laplacian deformer (volume_deformer.hpp): coarse-to-fine rigid patch levels,
// dense iterations and appearance-flow iterations, each step merging the targets of the
// correspondence sources (one file each: patch_targets, dense_targets, crease_targets,
// coverage_targets, feature_constraints, appearance_flow), then the checks of pairwise_checks.
// Every source takes its targets only from the observed part of the child's reconstruction (not
// on or near a hole's rim) and sets none on the template's closing surface (observed_surface.hpp,
// template_closing.hpp); the residuals are over the template vertices observed in the child.

#include <Eigen/Core>
#include <vector>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/appearance_flow.hpp"
#include "surfcap/align/coverage_targets.hpp"
#include "surfcap/align/crease_targets.hpp"
#include "surfcap/align/dense_targets.hpp"
#include "surfcap/align/image_features.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_checks.hpp"
#include "surfcap/align/patch_targets.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/align/rigid_initialisation.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

/// The schedule's own knobs, then one group per correspondence source (core/option_table.hpp).
struct PairwiseOptions {
  int patches = 30;                 ///< rigid patches at the coarsest level (casas2011: 30)
  int levels = 4;                   ///< patch levels, doubling the count each level
  /// Fit-and-solve passes of the coarsest level: each refits the patches from where the last solve
  /// left the template, so a limb that moved farther than one fit follows (a runner's shin) is
  /// reached before the finer levels' smaller gates take over.
  int coarse_passes = 3;
  int patch_icp_iterations = 6;
  int rotation_iterations = 3;      ///< rotation updates (solves) per level and per dense iteration
  double patch_weight = 0.09;       ///< soft-constraint weight of a patch target (relative to L's diagonal)
  double min_patch_inliers = 0.5;   ///< a patch fit is used if this fraction of its vertices found a match
  int dense_iterations = 4;
  double dense_weight = 0.3;        ///< weight of a dense closest-point target
  double normal_compatibility = 0.5;  ///< minimum cosine between normals of matched points
  double coarse_distance_height = 0.08;  ///< correspondence gate at level 0 (fraction of the template's height)
  double dense_distance_edges = 3;  ///< dense-fit gate (template mean edges)
  int heading_samples = 12;         ///< headings tried when the frames do not overlap rigidly
  /// Search the coarsest patches that fold the template onto itself about their joints
  /// (patch_targets.hpp); not an option: the tree alignment sets it to align a folded frame again.
  bool unfold = false;
  /// The rigid initialisation fits every point rather than the closest half (rigid_initialisation.hpp);
  /// not an option: the tree alignment sets it, with unfold, for a frame still folded after the
  /// joint search.
  bool whole_body_start = false;
  ColorOptions color;
  PatchColorOptions patch_color;
  PredictionOptions prediction;
  FeatureOptions feature;
  CoverageOptions coverage;
  CreaseOptions crease;
  FlowOptions flow;
  PairwiseCheckOptions checks;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("patches", self.patches, "Rigid patches at the coarsest level (doubling per level)", Range::at_least(1));
    t.field("levels", self.levels, "Coarse-to-fine patch levels", Range::closed(0, 10));
    t.field("coarse_passes", self.coarse_passes, "Fit-and-solve passes of the coarsest patch level",
            Range::closed(1, 10));
    t.field("patch_icp_iterations", self.patch_icp_iterations, "ICP iterations per patch fit", Range::at_least(1));
    t.field("rotation_iterations", self.rotation_iterations, "Rotation updates (solves) per level", Range::at_least(1));
    t.field("patch_weight", self.patch_weight, "Soft-constraint weight of patch targets", Range::above(0));
    t.field("min_patch_inliers", self.min_patch_inliers, "Fraction of a patch's vertices that must find a match",
            Range::above_to(0, 1));
    t.field("dense_iterations", self.dense_iterations, "Dense closest-point fitting iterations", Range::at_least(0));
    t.field("dense_weight", self.dense_weight, "Soft-constraint weight of dense targets", Range::above(0));
    t.field("normal_compatibility", self.normal_compatibility, "Minimum cosine between matched normals",
            Range::closed(-1, 1));
    t.field("coarse_distance_height", self.coarse_distance_height,
            "Correspondence gate at the coarsest level (fraction of the template height)", Range::above(0));
    t.field("dense_distance_edges", self.dense_distance_edges, "Dense-fit gate (template mean edges)", Range::above(0));
    t.field("heading_samples", self.heading_samples, "Headings tried when frames do not overlap rigidly",
            Range::at_least(1));
    t.group("color", self.color);
    t.group("patch_color", self.patch_color);
    t.group("prediction", self.prediction);
    t.group("feature", self.feature);
    t.group("coverage", self.coverage);
    t.group("crease", self.crease);
    t.group("flow", self.flow);
    t.inline_group(self.checks);
  }
  /// Throws bad_arguments naming the offending option.
  void validate() const { core::validate_options(*this); }
  core::Json to_json() const { return core::options_to_json(*this); }
};

struct PairwiseTimings {
  double matching = 0;       ///< closest points, ICP
  double factorisation = 0;  ///< Cholesky factorisations
  double solves = 0;         ///< rotation fits + back-substitutions
};

struct PairwiseResult {
  Eigen::MatrixXd positions;  ///< all deformer vertices (surface first), metres
  long patch_constraints = 0;   ///< vertices constrained by accepted patch fits (summed over levels)
  long dense_constraints = 0;   ///< closest-point constraints of the last dense iteration
  long feature_constraints = 0; ///< image feature matches used (0: geometric only)
  long color_constraints = 0;   ///< dense targets moved by vertex colours (last dense iteration)
  long coverage_constraints = 0;  ///< uncovered reconstruction vertices pulling the template (last solve)
  long flow_pixels = 0;         ///< pixel correspondences of the appearance flow (last flow iteration)
  long flow_vertices = 0;       ///< template vertices with a flow target (last flow iteration)
  int accepted_patches = 0, total_patches = 0;
  int color_patches = 0;        ///< patch fits taken from the colour-aware matching
  bool predicted = false;       ///< a motion prediction was given (align_pair's predicted_surface)
  int predicted_patches = 0;    ///< patch fits taken from the motion-predicted start
  int hinged_patches = 0;       ///< folded patches refitted about a joint (patch_targets.hpp)
  int carried_patches = 0;      ///< off-surface coarsest patches refitted from a neighbour's fit (patch_targets.hpp)
  double heading_change = 0;    ///< radians, of the rigid initialisation
  double mean_residual = 0;     ///< mean distance aligned surface vertex → reconstruction (m), observed vertices
  double max_residual = 0;
  double uncovered_fraction = 0;  ///< of the reconstruction's vertices, far from the aligned template
  /// Of the template's surface vertices, those in stacked layers (pairwise_checks.hpp).
  double stacked_fraction = 0;
  /// Template surface regions fused by the child's reconstruction with another part (legs joined,
  /// an arm fused to the torso; pairwise_checks.hpp `merged_regions`): their count and the
  /// fraction of the template's surface vertices in them.
  long merged_regions = 0;
  double merged_fraction = 0;
  long crease_constraints = 0;  ///< template crease vertices drawn to the reconstruction's creases (last solve)
  long holes = 0;                    ///< holes left open in the child's reconstruction
  double largest_hole_perimeter = 0;  ///< metres
  /// Of the template's surface vertices, those with no observation in the child: the closing
  /// surface, and the vertices whose closest reconstruction point lies on a hole's rim.
  double unobserved_fraction = 0;
  PairwiseTimings timings;
};

/// The camera-image features of the parent and child frames (either may be empty: no images).
struct FeaturePair {
  const FrameFeatures* parent = nullptr;
  const FrameFeatures* child = nullptr;
  /// The template's root appearance and the child frame's camera views (of the reconstruction
  /// align_pair aligns to): enable the flow iterations.
  const TemplateAppearance* appearance = nullptr;
  const ChildViews* child_views = nullptr;
  /// The capture's cameras (images or not): the coverage pulls and the uncovered check count only
  /// reconstruction vertices that some camera sees outside the aligned template's silhouette
  /// (silhouette_evidence.hpp). Null or empty: every far vertex counts.
  const std::vector<render::Camera>* cameras = nullptr;
};

/// Aligns the template from `parent_positions` (all deformer vertices) onto `target` (the child's
/// reconstruction, queried through `target_query`); `target_colors` (per target vertex, 0..1) enables
/// the photometric dense fit and the colour-aware patches when the template has colours too.
/// `predicted_surface` (template surface vertices, world), when given, is where a motion
/// prediction expects the child: the coarsest patch levels also try it as a start
/// (PredictionOptions::levels).
PairwiseResult align_pair(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                          const geometry::SurfaceQuery& target_query, const PairwiseOptions& options,
                          const Eigen::MatrixXd* target_colors = nullptr, const FeaturePair& features = {},
                          const Eigen::MatrixXd* predicted_surface = nullptr);

}  // namespace surfcap::align
