#pragma once
// Image feature correspondences (casas2011 §3.2): SIFT keypoints in every camera image of a frame,
// back-projected to the visible surface of its reconstruction by ray casting (the first hit of the
// camera ray, CGAL AABB tree), then matched between a parent and a child frame with FLANN
// (ratio test, mutual check, rejection of matches whose displacement disagrees with their
// neighbours'). OpenCV and FLANN stay inside image_features.cpp.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

struct FeatureOptions {
  /// Soft-constraint weight of a feature match, at every level and dense iteration; off: geometry only.
  std::optional<double> weight = 0.6;
  int max_per_image = 2000;       ///< strongest SIFT keypoints kept per image
  double ratio = 0.8;             ///< Lowe's ratio test: best / second-best descriptor distance
  int neighbours = 8;             ///< matches compared for the neighbour consistency check
  double neighbour_tolerance_height = 0.04;  ///< max deviation from the neighbours' median displacement
  double max_displacement_height = 0.35;     ///< matches moving farther after the rigid initialisation are rejected
  double min_facing = 0.3;        ///< minimum cosine between the hit's normal and the ray back to the camera

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("weight", self.weight, "Weight of image feature matches", Range::above(0));
    t.field("max_per_image", self.max_per_image, "Strongest SIFT keypoints kept per image", Range::at_least(1));
    t.field("ratio", self.ratio, "Ratio test of the feature matching", Range::above_to(0, 1));
    t.field("neighbours", self.neighbours, "Matches compared for the neighbour consistency check",
            Range::at_least(1));
    t.field("neighbour_tolerance_height", self.neighbour_tolerance_height,
            "Max deviation from the neighbours' median displacement (fraction of the height)", Range::above(0));
    t.field("max_displacement_height", self.max_displacement_height,
            "Matches moving farther than this after the rigid initialisation are rejected (fraction of the height)",
            Range::above(0));
    t.field("min_facing", self.min_facing, "Minimum cosine between the feature's normal and the camera ray",
            Range::from_below(0, 1));
  }
};

/// The features of one frame: 3-D points on its reconstruction, their normals and descriptors.
struct FrameFeatures {
  Eigen::MatrixXd points;   ///< k×3, on the reconstruction (metres)
  Eigen::MatrixXd normals;  ///< k×3, face normals at the points
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> descriptors;  ///< k×128
  std::vector<int> cameras;  ///< k: the camera each feature was seen in
  long detected = 0;         ///< keypoints before back-projection (all images)
  long size() const { return points.rows(); }
};

/// OpenCV's image processing (SIFT, optical flow) on the calling thread only: the alignment runs
/// its edges in parallel (`--threads`), so a job uses the cores it was given and no nested pool
/// beside them. The results are the same either way.
void serial_image_processing();

/// SIFT on every camera image of `sequence`:`frame` (frame number), back-projected onto
/// `reconstruction`. Empty when the capture has no images for the sequence. bad_input names an
/// unreadable image and its frame.
FrameFeatures detect_frame_features(const core::Capture& capture, int sequence, int frame,
                                    const geometry::SurfaceQuery& reconstruction, const FeatureOptions& options);

struct FeatureMatch {
  long parent = 0, child = 0;  ///< indices into the two FrameFeatures
};

/// Mutual best matches passing the ratio test, with consistent displacements: `predicted` maps
/// each parent point to where the child should roughly have it (k×3, e.g. after the rigid
/// initialisation), `height` scales the tolerances. Deterministic (exact kd-tree search).
std::vector<FeatureMatch> match_features(const FrameFeatures& parent, const FrameFeatures& child,
                                         const Eigen::MatrixXd& predicted, double height,
                                         const FeatureOptions& options);

}  // namespace surfcap::align
