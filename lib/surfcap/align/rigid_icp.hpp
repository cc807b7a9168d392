#pragma once
// Rigid ICP of a point set with normals onto a target surface: closest points with normal
// compatibility and a distance gate, point-to-plane with a small point-to-point term (so flat
// patches cannot slide away), linearised rotation per iteration. Used for whole-body rigid
// initialisation and for rigid patch matching (casas2011 §3.2).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

struct IcpOptions {
  int iterations = 6;
  double max_distance = 0.05;          ///< correspondences farther than this (m) are ignored
  double normal_compatibility = 0.5;   ///< minimum cosine between source and target normals
  double point_to_point_weight = 0.1;  ///< relative weight of the point-to-point term
};

struct RigidFit {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  long inliers = 0;            ///< compatible correspondences at the last iteration
  double mean_distance = 0;    ///< over the inliers at the last iteration (m)
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return rotation * p + translation; }
};

/// Compatible correspondence of one source point: the closest target point, if it is within
/// max_distance and its face normal agrees with `normal`.
bool compatible_closest_point(const geometry::SurfaceQuery& target, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& normal, double max_distance, double normal_compatibility,
                              geometry::SurfacePoint& closest);

/// Fits the rigid motion of `points` (k×3, with unit `normals` k×3) onto `target`, starting from
/// `initial`. The result maps the original points.
RigidFit fit_rigid(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const geometry::SurfaceQuery& target,
                   const IcpOptions& options, const RigidFit& initial = {});

}  // namespace surfcap::align
