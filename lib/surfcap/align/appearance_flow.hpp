#pragma once
// Dense, drift-free image correspondences for the alignment: the template, deformed to its current
// estimate of a child frame, is rendered into every camera of the child with the appearance the
// ROOT frame's cameras recorded for each template surface point; dense optical flow (OpenCV DIS)
// from that prediction to the child's real image moves each visible template point to where the
// child shows it, and the moved pixel's camera ray, cast onto the child's reconstruction, is its
// 3-D target. Because the reference appearance is the root's (not the parent's), the error of one
// tree edge is not inherited by the next: tangential sliding does not accumulate with tree depth.
// OpenCV stays inside appearance_flow.cpp.

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/geometry/surface_query.hpp"
#include "surfcap/render/camera.hpp"

namespace surfcap::align {

struct FlowOptions {
  /// Soft-constraint weight of a flow target (relative to L's diagonal); off: no flow iterations.
  std::optional<double> weight = 0.6;
  int iterations = 3;              ///< flow iterations after the dense fit (render, flow, solve)
  int stride = 1;                  ///< pixel step of the constraint grid
  int margin_px = 24;              ///< flow is computed in the template's image bounding box plus this margin
  double consistency_px = 0.5;     ///< max disagreement of the forward and backward flow, pixels
  double max_offset_edges = 8.0;   ///< a target farther than this from its template point is dropped (mean edges)
  double min_facing = 0.3;         ///< cosine between surface normal and view ray (root, template and child)
  double visibility_edges = 0.3;   ///< depth tolerance of the root cameras' visibility test (mean edges)
  double normal_compatibility = 0.5;  ///< cosine between the template's and the reconstruction's normals

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("weight", self.weight, "Weight of the appearance-flow targets", Range::above(0));
    t.field("iterations", self.iterations, "Appearance-flow iterations after the dense fit", Range::at_least(0));
    t.field("stride", self.stride, "Pixel step of the appearance-flow constraints", Range::closed(1, 16));
    t.field("margin_px", self.margin_px, "Flow computed in the template's image box plus this margin (pixels)",
            Range::at_least(0));
    t.field("consistency_px", self.consistency_px, "Max disagreement of forward and backward flow (pixels)",
            Range::above(0));
    t.field("max_offset_edges", self.max_offset_edges,
            "Flow targets farther than this from their template point are dropped (mean edges)", Range::above(0));
    t.field("min_facing", self.min_facing, "Minimum cosine between surface normal and view ray",
            Range::from_below(0, 1));
    t.field("visibility_edges", self.visibility_edges, "Depth tolerance of the root cameras' visibility (mean edges)",
            Range::above(0));
    t.field("normal_compatibility", self.normal_compatibility,
            "Minimum cosine between template and reconstruction normals of a flow target", Range::closed(-1, 1));
  }
};

/// A grey image (0..1), row-major.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<float> pixels;
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)]; }
  /// Bilinear sample at pixel coordinates (pixel centres at integers); nullopt outside.
  std::optional<double> sample(double x, double y) const;
};

/// The camera images of `sequence`:`frame` as grey images, in the capture's camera order; empty when
/// the sequence has no images. bad_input names an unreadable image or one of the wrong size.
std::vector<GreyImage> read_grey_images(const core::Capture& capture, int sequence, int frame);

/// The cameras of the capture (render convention). Flow needs undistorted images: has_distortion()
/// tells whether any camera declares lens distortion (then flow is not used).
std::vector<render::Camera> capture_cameras(const core::Capture& capture);
bool has_distortion(const core::Capture& capture);

/// How the root frame's cameras saw the template: for a surface point, the grey value of the root
/// images where it is visible and facing the camera (blended by cos² of the viewing angle).
class TemplateAppearance {
 public:
  TemplateAppearance(const core::Mesh& root_surface, std::vector<render::Camera> cameras,
                     std::vector<GreyImage> root_images, double mean_edge, const FlowOptions& options);
  /// Grey value of the template point (face, barycentric); nullopt where no root camera saw it.
  /// With `camera` ≥ 0, that root camera's own sample where it sees the point (the blend elsewhere).
  std::optional<double> value(long face, const Eigen::Vector3d& barycentric, int camera = -1) const;
  const std::vector<render::Camera>& cameras() const { return cameras_; }
  /// Fraction of template faces (at their centroids) seen by at least one root camera.
  double coverage() const { return coverage_; }

 private:
  /// The blend over the root cameras that see the point, or only camera `only` (≥ 0).
  std::optional<double> sample(long face, const Eigen::Vector3d& barycentric, int only) const;
  Eigen::MatrixXd V_;
  Eigen::MatrixXi F_;
  Eigen::MatrixXd face_normals_;
  std::vector<render::Camera> cameras_;
  std::vector<GreyImage> images_;
  std::vector<std::vector<float>> depth_;  ///< per root camera: depth of the visible template surface
  double tolerance_ = 0;
  double min_facing_ = 0;
  double coverage_ = 0;
};

/// Per template surface vertex, where the child's images show it.
struct FlowTargets {
  Eigen::MatrixXd targets;  ///< n×3 (rows without support: the current position)
  Eigen::VectorXd support;  ///< n: summed barycentric weight of the pixels behind the target (0: none)
  long pixels = 0;          ///< accepted pixel correspondences (all cameras)
};

/// The child frame as the cameras show it: its reconstruction, its grey camera images (the
/// capture's camera order) and, rendered on first use and kept for every flow iteration and attempt
/// of an edge, the reconstruction's face at each pixel. Used by one thread at a time.
class ChildViews {
 public:
  /// `reconstruction` must outlive the views.
  ChildViews(const geometry::SurfaceQuery& reconstruction, std::vector<GreyImage> images);
  const geometry::SurfaceQuery& reconstruction() const { return *reconstruction_; }
  const std::vector<GreyImage>& images() const { return images_; }
  /// The face seen at each pixel (row-major, −1 where none) by camera `c`, which is `camera`.
  const std::vector<int>& faces(std::size_t c, const render::Camera& camera) const;

 private:
  const geometry::SurfaceQuery* reconstruction_;
  std::vector<GreyImage> images_;
  mutable std::vector<std::vector<int>> faces_;  ///< per camera; empty until rendered
};

/// Flow targets for the template surface `surface` (n×3, faces F) against the child frame's images
/// and reconstruction. Per vertex, the target is the component-wise weighted median of the offsets
/// of the accepted pixels on its faces. Deterministic: cameras in order (OpenCV's DIS splits its
/// work into fixed stripes).
FlowTargets flow_targets(const TemplateAppearance& appearance, const Eigen::MatrixXd& surface,
                         const Eigen::MatrixXi& F, const ChildViews& child, double mean_edge,
                         const FlowOptions& options);

/// The weighted median of `values` (value, weight > 0): the least value whose weight together with
/// that of every smaller value reaches half the total (the largest value if rounding keeps the sum
/// below half; NaN when empty). Quickselect, O(n) expected; reorders `values`. Per coordinate of
/// the flow offsets.
double weighted_median(std::vector<std::pair<double, double>>& values);

/// Sets the targets of the vertices with flow support (weight × min(1, support)), overriding any
/// other target there; returns how many.
long set_flow_targets(const FlowTargets& flow, double weight, Eigen::MatrixXd& targets, Eigen::VectorXd& weights);

}  // namespace surfcap::align
