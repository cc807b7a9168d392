#pragma once
// Image feature correspondences (casas2011 §3.2): SIFT keypoints in every camera image of a frame,
// back-projected to the visible surface of its reconstruction by ray casting (the first hit of the
// camera ray, CGAL AABB tree), then matched between a parent and a child frame with FLANN
// (ratio test, mutual check, rejection of matches whose displacement disagrees with their
// neighbours'). OpenCV and FLANN stay inside image_features.cpp.

#include <Eigen/Core>
#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

struct FeatureOptions {
  int max_per_image = 2000;       ///< strongest SIFT keypoints kept per image
  double min_facing = 0.3;        ///< minimum cosine between the hit's normal and the ray back to the camera
  double ratio = 0.8;             ///< Lowe's ratio test: best / second-best descriptor distance
  int neighbours = 8;             ///< matches compared for the neighbour consistency check
  double neighbour_tolerance = 0.04;  ///< max deviation from the neighbours' median displacement, fraction of height
  double max_displacement = 0.35;     ///< matches moving more than this (fraction of height) after the rigid
                                      ///< initialisation are rejected
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
