#pragma once
// Pairwise non-rigid alignment (casas2011 §3.2): the template, already aligned to a parent frame,
// deformed onto a child frame's reconstruction. Rigid initialisation (with a heading search when
// the frames face differently), then coarse-to-fine rigid patch matching (30 patches, doubling per
// level) as soft constraints of the volumetric Laplacian deformer, then a dense fit to the surface.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "surfcap/align/appearance_flow.hpp"
#include "surfcap/align/image_features.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/align/surface_patches.hpp"
#include "surfcap/align/volume_deformer.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

/// Photometric dense fit: when both meshes have vertex colours, each dense target is the
/// colour-weighted mean of the reconstruction vertices near the closest point.
struct ColorOptions {
  std::optional<double> sigma = 0.15;  ///< colour σ (RGB 0..1); off: geometry only
  double radius_edges = 1.5;           ///< search radius of the photometric target (template mean edges)

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("sigma", self.sigma, "Photometric dense fit: colour sigma (RGB 0..1)", core::Range::above(0));
    t.field("radius_edges", self.radius_edges, "Search radius of the photometric target (template mean edges)",
            core::Range::above(0));
  }
};

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
struct PredictionOptions {
  int levels = 1;
  double gain = 0.8;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("levels", self.levels, "Patch levels that also try the motion-predicted start", core::Range::at_least(0));
    t.field("gain", self.gain, "Predicted patch fit used when its mean distance is below this fraction of the other fit's",
            core::Range::above_to(0, 1));
  }
};

/// Coverage pulls: reconstruction vertices left uncovered by the aligned template pull their
/// closest template point, with this weight per vertex.
struct CoverageOptions {
  std::optional<double> weight = 0.9;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("weight", self.weight, "Weight of the coverage (reconstruction to template) pulls", core::Range::above(0));
  }
};

/// Crease matching (creases.hpp): template vertices on a convex crease of the rest surface
/// (dihedral angle > `angle_deg`) are drawn to the closest point of the reconstruction's convex
/// creases within `distance_edges` (bisector within the normal gate), with this weight, replacing
/// their closest-point target. Only straight stretches of the template's creases are matched
/// (straight_crease_vertices: sqrt(λ₂/λ₁) of the crease vertices within `straight_radius_height`
/// ≤ `straightness`; off: every crease vertex). The radius is a body scale (a hand's crease loop is
/// a whole loop within it at any mesh resolution), not a number of edges.
struct CreaseOptions {
  std::optional<double> weight = 0.3;
  double angle_deg = 50;
  double distance_edges = 4;
  std::optional<double> straightness = 0.45;
  double straight_radius_height = 0.048;
  int patch_levels = 2;  ///< crease matching also at the last this many patch levels (always in the dense fit)

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("weight", self.weight, "Weight of crease matching: template rim vertices to the reconstruction's creases",
            Range::above(0));
    t.field("angle_deg", self.angle_deg, "Dihedral angle above which a convex edge is a crease", Range::open(0, 180));
    t.field("distance_edges", self.distance_edges, "Crease matching gate (template mean edges)", Range::above(0));
    t.field("straightness", self.straightness,
            "Match only straight template crease stretches: max sqrt(l2/l1) of nearby crease vertices", Range::above(0));
    t.field("straight_radius_height", self.straight_radius_height,
            "Neighbourhood of the straightness test (fraction of the template height)", Range::above(0));
    t.field("patch_levels", self.patch_levels, "Crease matching also at the last N patch levels", Range::at_least(0));
  }
};

/// What an aligned pair is checked for (PairwiseResult's uncovered and stacked fractions).
struct PairwiseCheckOptions {
  /// A reconstruction vertex farther than this from the aligned template (mean edges) is uncovered.
  double uncovered_distance_edges = 1.5;
  /// Stacked layers: two aligned template vertices closer than `stacked_distance_edges`, facing
  /// the same way (normals' cosine above 0.5), that lie more than `stacked_rest_distance_height`
  /// apart at rest.
  double stacked_distance_edges = 0.5;
  double stacked_rest_distance_height = 0.057;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("uncovered_distance_edges", self.uncovered_distance_edges,
            "A reconstruction vertex farther than this from the aligned template is uncovered (mean edges)",
            Range::above(0));
    t.field("stacked_distance_edges", self.stacked_distance_edges,
            "Aligned template vertices closer than this may be stacked layers (mean edges)", Range::above(0));
    t.field("stacked_rest_distance_height", self.stacked_rest_distance_height,
            "... when farther apart than this at rest (fraction of the template height)", Range::above(0));
  }
};

struct PairwiseOptions {
  int patches = 30;                 ///< rigid patches at the coarsest level (casas2011: 30)
  int levels = 4;                   ///< patch levels, doubling the count each level
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

/// What is computed once per template and shared (read-only) by every pairwise alignment.
class AlignmentTemplate {
 public:
  AlignmentTemplate(core::Mesh mesh, const PairwiseOptions& options, const DeformerOptions& deformer = {});
  const core::Mesh& mesh() const { return mesh_; }
  const VolumeDeformer& deformer() const { return deformer_; }
  const std::vector<PatchSet>& patches() const { return patches_; }
  /// The template's vertex colours smoothed for colour-aware patch matching (empty: no colours).
  const Eigen::MatrixXd& smoothed_colors() const { return smoothed_colors_; }
  /// Vertices on a convex crease of the template at rest (CreaseOptions::angle_deg).
  const std::vector<int>& crease_vertices() const { return crease_vertices_; }
  double mean_edge() const { return mean_edge_; }
  double height() const { return height_; }  ///< extent along y at rest (m)
  double seconds_tetrahedralisation() const { return seconds_tetrahedralisation_; }

 private:
  double seconds_tetrahedralisation_ = 0;  // before deformer_: its initialiser sets it
  core::Mesh mesh_;
  VolumeDeformer deformer_;
  std::vector<PatchSet> patches_;
  Eigen::MatrixXd smoothed_colors_;
  std::vector<int> crease_vertices_;
  double mean_edge_ = 0;
  double height_ = 0;
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
  double heading_change = 0;    ///< radians, of the rigid initialisation
  double mean_residual = 0;     ///< mean distance aligned surface vertex → reconstruction (m)
  double max_residual = 0;
  double uncovered_fraction = 0;  ///< of the reconstruction's vertices, far from the aligned template
  /// Of the template's surface vertices, those in stacked layers: laid onto the same stretch of
  /// surface as a part of the template far from them at rest (a hand pushed up its forearm, a limb
  /// laid onto another) — a fold the one- and two-sided residuals cannot see.
  double stacked_fraction = 0;
  long crease_constraints = 0;  ///< template crease vertices drawn to the reconstruction's creases (last solve)
  PairwiseTimings timings;
};

/// Vertex colours averaged with their neighbours' `rings` times (uniform weights).
Eigen::MatrixXd smoothed_vertex_colors(const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors, int rings);

/// Per surface vertex of `surface` (n×3 template connectivity): distance to the target surface.
Eigen::VectorXd surface_distances(const Eigen::MatrixXd& surface, const geometry::SurfaceQuery& target);

/// The camera-image features of the parent and child frames (either may be empty: no images).
struct FeaturePair {
  const FrameFeatures* parent = nullptr;
  const FrameFeatures* child = nullptr;
  /// The template's root appearance and the child's camera images (grey): enable the flow iterations.
  const TemplateAppearance* appearance = nullptr;
  const std::vector<GreyImage>* child_images = nullptr;
};

/// Fraction of the vertices of `aligned` (the template surface posed, faces F) in stacked layers:
/// within `distance` of another vertex with a normal at less than 60° from theirs that lies more
/// than `rest_distance` from them in `rest`. A surface laid onto itself (a hand pushed up its
/// forearm: the hand's vertices on the forearm's stretch of the reconstruction) is a fold the
/// residuals cannot see; two parts that touch face each other and do not count.
double stacked_fraction(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                        double distance, double rest_distance);

/// Whole-body rigid initialisation of a template surface (vertex normals `normals`) onto `target`:
/// centroids matched, ICP; if the result does not overlap, the best of `heading_samples` rotations
/// about the vertical axis (similar frames of different sequences may face differently: the shape
/// similarity is invariant to heading).
RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options);

/// Aligns the template from `parent_positions` (all deformer vertices) onto `target` (the child's
/// reconstruction, queried through `target_query`); `target_colors` (per target vertex, 0..1) enables
/// the photometric dense fit when the template has colours too. `predicted_surface` (template
/// surface vertices, world), when given, is where a motion prediction expects the child: the
/// coarsest patch levels also try it as a start (PredictionOptions::levels).
PairwiseResult align_pair(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                          const geometry::SurfaceQuery& target_query, const PairwiseOptions& options,
                          const Eigen::MatrixXd* target_colors = nullptr, const FeaturePair& features = {},
                          const Eigen::MatrixXd* predicted_surface = nullptr);

}  // namespace surfcap::align
