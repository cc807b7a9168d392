#pragma once
// Image feature matches as soft constraints of the deformation (casas2011 §3.2): a parent feature
// lies on the parent's reconstruction, which the aligned template covers; its closest point on the
// aligned template surface (face + barycentric coordinates) is the template point that must move
// to the matched child feature.

#include <Eigen/Core>
#include <vector>

#include "surfcap/align/image_features.hpp"

namespace surfcap::align {

struct FeatureConstraint {
  long face = 0;                 ///< template face
  Eigen::Vector3d barycentric;   ///< in it
  Eigen::Vector3d target;        ///< the child feature (world, metres)
};

/// Template points of the parent features (aligned `parent_surface`, template faces `F`): features
/// farther than `max_distance` from the aligned surface or facing away from it are dropped.
/// `transform` (applied to the template points) predicts the child positions for the matching.
struct FeatureMatching {
  std::vector<FeatureConstraint> constraints;
  long candidates = 0;  ///< parent features on the aligned template
};
FeatureMatching feature_constraints(const Eigen::MatrixXd& parent_surface, const Eigen::MatrixXi& F,
                                    const FrameFeatures& parent, const FrameFeatures& child,
                                    const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                                    double max_distance, double height, const FeatureOptions& options);

/// Adds the constraints at the current `surface` to per-vertex soft targets: each constraint pulls
/// its face's corners by the offset of its template point, weighted by `weight` × barycentric;
/// where a vertex already has a target, the two are merged (weighted mean, weights summed).
void add_feature_targets(const Eigen::MatrixXd& surface, const Eigen::MatrixXi& F,
                         const std::vector<FeatureConstraint>& constraints, double weight, Eigen::MatrixXd& targets,
                         Eigen::VectorXd& weights);

}  // namespace surfcap::align
