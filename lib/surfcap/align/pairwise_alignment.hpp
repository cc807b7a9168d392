#pragma once
// Pairwise non-rigid alignment (casas2011 §3.2): the template, already aligned to a parent frame,
// deformed onto a child frame's reconstruction. Rigid initialisation (with a heading search when
// the frames face differently), then coarse-to-fine rigid patch matching (30 patches, doubling per
// level) as soft constraints of the volumetric Laplacian deformer, then a dense fit to the surface.

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "surfcap/align/appearance_flow.hpp"
#include "surfcap/align/image_features.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/align/surface_patches.hpp"
#include "surfcap/align/volume_deformer.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

struct PairwiseOptions {
  int initial_patches = 30;         ///< patches at the coarsest level (casas2011: 30)
  int levels = 4;                   ///< patch levels, doubling the count each level
  int patch_icp_iterations = 6;
  int rotation_iterations = 3;      ///< rotation updates (solves) per level and per dense iteration
  double patch_weight = 0.09;       ///< soft-constraint weight of a patch target (relative to L's diagonal)
  double min_patch_inliers = 0.5;   ///< a patch fit is used if this fraction of its vertices found a match
  int dense_iterations = 4;
  double dense_weight = 0.3;        ///< weight of a dense closest-point target
  double normal_compatibility = 0.5;  ///< minimum cosine between normals of matched points
  double coarse_distance = 0.08;    ///< correspondence gate at level 0, fraction of the template's height
  double dense_distance_edges = 3;  ///< dense-fit gate, in template mean edge lengths
  int heading_samples = 12;         ///< headings tried when the frames do not overlap rigidly
  /// Photometric dense fit: when both meshes have vertex colours, each dense target is the
  /// colour-weighted mean of the target vertices near the closest point (σ in RGB 0..1; ≤ 0: off).
  double color_sigma = 0.15;
  double color_radius_edges = 1.5;  ///< search radius of the photometric target, in template mean edges
  /// Colour-aware rigid patch matching at the coarsest `patch_color_levels` levels, when both meshes
  /// have colours: besides its closest-point fit, each patch is fitted with correspondences found in
  /// position-colour space (nearest reconstruction vertex with this many metres per unit of RGB, then
  /// the closest point of that vertex's faces; ≤ 0: off), with vertex colours smoothed over
  /// `color_smoothing` rings on both meshes (texture detail averaged out, part colours kept); the
  /// colour fit is taken when its colours agree clearly better (`patch_color_gain`).
  double patch_color_scale = 1.0;
  int patch_color_levels = 2;  ///< colour-aware at the coarsest this many patch levels (then closest points)
  /// A patch's colour-aware fit replaces its closest-point fit when its colour disagreement is below
  /// this fraction of the closest-point fit's.
  double patch_color_gain = 0.8;
  int color_smoothing = 2;
  /// Motion prediction (when align_pair is given a predicted surface): at the coarsest
  /// `prediction_levels` levels each patch is also fitted from its predicted pose; that fit is
  /// taken when its clamped mean distance to the reconstruction is below `prediction_gain` × the
  /// other fit's, with no fewer inliers.
  int prediction_levels = 1;
  double prediction_gain = 0.8;
  /// Image features (SIFT matches between the parent's and the child's camera images): soft
  /// constraints at every level and dense iteration, each with this weight (≤ 0: not used).
  double feature_weight = 0.6;
  FeatureOptions features;
  /// Coverage constraints: reconstruction vertices left uncovered by the aligned template pull their
  /// closest template point, with this weight per vertex (≤ 0: off).
  double coverage_weight = 0.9;
  /// Dense optical flow against the root frame's appearance (appearance_flow.hpp): iterations after
  /// the dense fit, when the template's root appearance and the child's images are given.
  FlowOptions flow;
  double uncovered_distance_edges = 1.5;  ///< a reconstruction vertex farther than this from the aligned
                                          ///< template (template mean edges) is uncovered
  /// Stacked layers (PairwiseResult::stacked_fraction): two aligned template vertices closer than
  /// `stacked_distance_edges` (template mean edges), facing the same way (normals' cosine above
  /// 0.5), that lie more than `stacked_rest_distance` (fraction of the template height) apart at rest.
  double stacked_distance_edges = 0.5;
  double stacked_rest_distance = 0.057;
  /// Crease matching (creases.hpp): template vertices on a convex crease of the rest surface
  /// (dihedral angle > `crease_angle_deg`) are drawn to the closest point of the reconstruction's
  /// convex creases within `crease_distance_edges` (bisector within the normal gate), with this
  /// weight, replacing their closest-point target (≤ 0: off).
  double crease_weight = 0.3;
  double crease_angle_deg = 50;
  double crease_distance_edges = 4;
  /// Only straight stretches of crease are matched (straight_crease_vertices: sqrt(λ₂/λ₁) of the
  /// crease vertices within `crease_straight_radius` ≤ this), on the template and, with
  /// `crease_target_straightness` < 1, on the reconstruction; ≥ 1 = every crease vertex. The
  /// radius is a fraction of the template height, a body scale (a hand's crease loop is a whole
  /// loop within it at any mesh resolution), not a number of edges.
  double crease_straightness = 0.45;
  double crease_target_straightness = 1;
  double crease_straight_radius = 0.048;
  int crease_patch_levels = 2;  ///< crease matching also at the last this many patch levels (always in the dense fit)
  /// Throws bad_arguments naming the offending option.
  void validate() const;
  core::Json to_json() const;
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
  /// Vertices on a convex crease of the template at rest (PairwiseOptions::crease_angle_deg).
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
/// coarsest patch levels also try it as a start (PairwiseOptions::prediction_levels).
PairwiseResult align_pair(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                          const geometry::SurfaceQuery& target_query, const PairwiseOptions& options,
                          const Eigen::MatrixXd* target_colors = nullptr, const FeaturePair& features = {},
                          const Eigen::MatrixXd* predicted_surface = nullptr);

}  // namespace surfcap::align
