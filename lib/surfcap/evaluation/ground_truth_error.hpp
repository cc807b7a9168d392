#pragma once
// Alignment error against a synthetic capture's ground truth (docs/synth.md). The template is the
// root frame's reconstruction, so each template vertex v has a true location on the true surface:
// the root reconstruction's correspondence (true face + barycentric). In every frame f the aligned
// v should lie at Σ_k b_vk · X_f[F[face_v, k]], X_f the true world positions of frame f. The
// vertices that close the holes of an open root reconstruction (align/template_closing.hpp) have no
// correspondence: the error is over the reconstruction's vertices, and of those over the ones on
// the true surface (with the studio models' correspondence status: not phantom volume, outliers or
// blobs, whose truth is only the nearest true point).

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::evaluation {

/// The true locations of the template's vertices (the root reconstruction's) in any frame.
class TruthReference {
 public:
  /// Reads <capture>/ground_truth/truth.json, the true database and the root's correspondence;
  /// bad_input if they are incomplete. The first `observed_vertices` template vertices are the
  /// root reconstruction's (< 0: all of them) but its `dropped_vertices` (ascending: the loose
  /// pieces the template leaves out), in order.
  TruthReference(const core::Capture& capture, const core::AlignedDatabase& aligned, long observed_vertices = -1,
                 const std::vector<long>& dropped_vertices = {});
  /// Template vertices with a true location (the root reconstruction's, first in the template).
  long vertex_count() const { return barycentric_.rows(); }
  /// Is template vertex v evaluated: on the true surface (status on_surface or rough; every
  /// vertex without a status file)?
  bool evaluated(long v) const { return evaluated_[static_cast<std::size_t>(v)] != 0; }
  /// Share of the template's vertices evaluated (of all its vertices, closing surface included).
  double evaluated_fraction() const { return evaluated_fraction_; }
  /// n×3 world positions of the template vertices in `sequence`:`frame` (frame number).
  Eigen::MatrixXd positions(const std::string& sequence, int frame) const;
  /// Per template vertex: is its true location seen by at least one of the capture's cameras in
  /// `sequence`:`frame` — the true surface faces the camera (cos > 0.1) and is not occluded by the
  /// true surface itself (depth test against its rendering, tolerance 0.5 % of the height)? All
  /// false when the capture has no cameras.
  std::vector<bool> observed(const std::string& sequence, int frame) const;
  double height() const { return height_; }  ///< the true root frame's y extent (m)
  /// Texture region per template vertex (regions.npy of the true template; −1 when absent).
  const Eigen::VectorXi& regions() const { return regions_; }
  const std::vector<std::string>& region_names() const { return region_names_; }
  /// Per template vertex: does the true surface face downwards at rest (normal y < −0.5)? The
  /// undersides — of the skirt (its hem, where the synth's truth stretches most), the chin, the
  /// soles — reported apart.
  const std::vector<bool>& downward() const { return downward_; }

 private:
  /// The true surface of `sequence`:`frame` in world coordinates (vertices of truth_.template_mesh).
  Eigen::MatrixXd true_vertices(const std::string& sequence, int frame) const;

  const core::Capture& capture_;
  std::filesystem::path truth_path_;
  core::AlignedDatabase truth_;
  std::vector<int> faces_;
  Eigen::MatrixXd barycentric_;
  Eigen::VectorXi regions_;
  std::vector<bool> downward_;
  std::vector<char> evaluated_;
  double evaluated_fraction_ = 1;
  std::vector<std::string> region_names_;
  double height_ = 0;
};

struct FrameTruthError {
  double rms = 0;  ///< metres, over the template vertices
  double max = 0;
  double normal_rms = 0;      ///< component along the true surface normal
  double tangential_rms = 0;  ///< component in the true tangent plane (sliding)
  double observed_fraction = 0;  ///< of the template vertices whose true location a camera sees
  std::vector<bool> observed;    ///< per template vertex (TruthReference::observed)
};

struct TruthEvaluation {
  double height = 0;                    ///< character height: the true root frame's y extent (m)
  /// Share of the template's vertices with a true location on the surface (TruthReference::evaluated).
  double evaluated_fraction = 1;
  double rms = 0;                       ///< over all frames and vertices (m)
  double normal_rms = 0, tangential_rms = 0;
  double worst_frame_rms = 0;
  long worst_node = 0;
  double p99_vertex_error = 0;          ///< 99th percentile of the vertex-frame errors (m)
  /// Split by whether a camera of the frame sees the vertex's true location (TruthReference::
  /// observed): the unobserved part (under the skirt, between the legs, in armpits) has no image
  /// evidence (SIFT, flow), only the reconstruction's geometry and the deformation prior. Zero
  /// fraction when the capture has no cameras.
  double observed_fraction = 0, observed_rms = 0, unobserved_rms = 0;
  std::vector<FrameTruthError> frames;  ///< per node
  std::map<int, double> rms_by_depth;   ///< tree depth → RMS over its frames and vertices
  std::map<std::string, double> rms_by_region;  ///< texture region → RMS over all frames
  /// texture region → the region's share of Σ squared error (all frames)
  std::map<std::string, double> squared_share_by_region;
  /// The same two over the region's downward-facing vertices (TruthReference::downward), and the
  /// fraction of the region's vertices that face downwards.
  std::map<std::string, double> downward_rms_by_region, downward_squared_share_by_region, downward_fraction_by_region;
  core::Json to_json(const align::Registration& registration) const;  ///< figures in metres and % of height
};

/// <capture>/ground_truth/truth.json if the capture has ground truth.
std::optional<std::filesystem::path> ground_truth_file(const core::Capture& capture);

/// Compares every aligned frame with the truth; bad_input if the ground truth is incomplete.
TruthEvaluation evaluate_against_truth(const TruthReference& truth, const align::Registration& registration);
TruthEvaluation evaluate_against_truth(const core::Capture& capture, const align::Registration& registration);

}  // namespace surfcap::evaluation
