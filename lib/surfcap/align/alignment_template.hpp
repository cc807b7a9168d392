#pragma once
// What is computed once per template and shared (read-only) by every pairwise alignment: the
// deformation model, the patch hierarchy, smoothed colours, the rest surface's crease vertices,
// which of its vertices and faces are observed (template_closing.hpp) and which vertices the
// root frame's cameras see.

#include <Eigen/Core>

#include <algorithm>
#include <vector>

#include "surfcap/align/surface_patches.hpp"
#include "surfcap/align/template_closing.hpp"
#include "surfcap/align/volume_deformer.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/render/camera.hpp"

namespace surfcap::align {

struct PairwiseOptions;

class AlignmentTemplate {
 public:
  AlignmentTemplate(core::Mesh mesh, const PairwiseOptions& options, const DeformerOptions& deformer = {});
  /// A template whose vertices and faces beyond `surface.observed_*` close the root
  /// reconstruction's holes: unobserved, no data target is set on them. `cameras`: the root
  /// frame's; the volume under the surface none of them sees is soft (VolumeDeformer).
  AlignmentTemplate(TemplateSurface surface, const PairwiseOptions& options, const DeformerOptions& deformer = {},
                    const std::vector<render::Camera>& cameras = {});
  const core::Mesh& mesh() const { return mesh_; }
  const VolumeDeformer& deformer() const { return deformer_; }
  const std::vector<PatchSet>& patches() const { return patches_; }
  /// The template's vertex colours smoothed for colour-aware patch matching (empty: no colours).
  const Eigen::MatrixXd& smoothed_colors() const { return smoothed_colors_; }
  /// Vertices on a straight convex crease of the template at rest (CreaseOptions).
  const std::vector<int>& crease_vertices() const { return crease_vertices_; }
  /// Is surface vertex v the reconstruction's (not the closing surface's)?
  bool observed_vertex(long v) const { return v < observed_vertices_; }
  /// Is face f the reconstruction's?
  bool observed_face(long f) const { return f < observed_faces_; }
  /// Does the template have a closing surface (unobserved vertices)?
  bool closed_by_fill() const { return observed_vertices_ < mesh_.vertex_count(); }
  /// Share of the template's surface vertices on the closing surface (0: the root frame was closed).
  double unobserved_fraction() const;
  /// Template vertices no root camera sees (0 without cameras, or when none sees the template).
  long unseen_vertex_count() const { return unseen_vertices_; }
  double mean_edge() const { return mean_edge_; }
  double height() const { return height_; }  ///< extent along y at rest (m)
  /// The factor of every target weight: the mean edge over kReferenceEdgeHeight of the height,
  /// at most 1. The deformer's weights are relative to the mean diagonal of its Laplacian, which
  /// grows with the edge length while the vertices per unit of surface grow with its inverse
  /// square: so scaled, a target on a template finer than the reference pulls as hard per unit of
  /// surface as on the reference, and the options' weights hold as stated. A coarser template keeps
  /// them as they are (its targets, each standing for more surface, are also less precise).
  double weight_scale() const { return std::min(1.0, mean_edge_ / (kReferenceEdgeHeight * height_)); }
  /// The template resolution the target weights are stated for: a mean edge of 1/80 of the
  /// height (2.2 cm on a 1.75 m body), the finest of the templates they were set on (1/73 to 1/78
  /// of the height, some 3,700 to 4,600 vertices).
  static constexpr double kReferenceEdgeHeight = 1.0 / 80;
  double seconds_tetrahedralisation() const { return seconds_tetrahedralisation_; }

 private:
  double seconds_tetrahedralisation_ = 0;  // before deformer_: its initialiser sets these two
  long unseen_vertices_ = 0;
  core::Mesh mesh_;
  VolumeDeformer deformer_;
  std::vector<PatchSet> patches_;
  Eigen::MatrixXd smoothed_colors_;
  std::vector<int> crease_vertices_;
  double mean_edge_ = 0;
  double height_ = 0;
  long observed_vertices_ = 0, observed_faces_ = 0;
};

/// Per vertex of (V, F): 1 where no face around it is visible in any camera (render_visibility at
/// the camera's resolution). Empty when no camera sees a face of the mesh: a calibration in another
/// frame of reference, or none, tells nothing about what was seen.
std::vector<char> unseen_vertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                  const std::vector<render::Camera>& cameras);

/// Vertex colours averaged with their neighbours' `rings` times (uniform weights).
Eigen::MatrixXd smoothed_vertex_colors(const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors, int rings);

}  // namespace surfcap::align
