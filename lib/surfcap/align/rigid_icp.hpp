#pragma once
// Rigid ICP of a point set with normals onto a target surface: closest points with normal
// compatibility and a distance gate, point-to-plane with a small point-to-point term (so flat
// patches cannot slide away), linearised rotation per iteration. Used for whole-body rigid
// initialisation and for rigid patch matching (casas2011 §3.2).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

struct IcpOptions {
  int iterations = 6;
  double max_distance = 0.05;          ///< correspondences farther than this (m) are ignored
  double normal_compatibility = 0.5;   ///< minimum cosine between source and target normals
  double point_to_point_weight = 0.1;  ///< relative weight of the point-to-point term
  /// Each iteration fits only this fraction of the compatible correspondences, the closest ones
  /// (trimmed ICP, Chetverikov et al. 2002): 1 fits them all.
  double trim_fraction = 1.0;
};

struct RigidFit {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  long inliers = 0;            ///< compatible correspondences at the last iteration
  double mean_distance = 0;    ///< over the inliers at the last iteration (m)
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return rotation * p + translation; }
};

/// The target's vertices in a joint space of position and colour, for colour-aware ("6-D")
/// correspondences (Johnson & Kang's colour ICP): the nearest vertex minimises
/// ‖p − q‖² + scale²‖c_p − c_q‖², so a patch of one colour is drawn to the part of the target that
/// shows that colour instead of to whatever surface is nearest (a raised shoe onto the trousers).
/// Exact k-d tree search (FLANN, single tree: deterministic). FLANN stays in rigid_icp.cpp.
class ColoredTarget {
 public:
  /// The target mesh (V, F), colours (0..1) per vertex; `scale` metres per unit of RGB.
  ColoredTarget(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors, double scale);
  ~ColoredTarget();
  ColoredTarget(const ColoredTarget&) = delete;
  ColoredTarget& operator=(const ColoredTarget&) = delete;
  /// Nearest target vertex of each query row (points k×3 with colours k×3), in the joint space.
  std::vector<int> nearest(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors) const;
  /// The point of the faces around target vertex `vertex` closest to `p`, and that face's normal:
  /// where the joint-space match is the vertex under p, this is p's own foot point (no pull along
  /// the surface from the vertex spacing); elsewhere, a point of the matching colour region.
  std::pair<Eigen::Vector3d, Eigen::Vector3d> closest_around(int vertex, const Eigen::Vector3d& p) const;

 private:
  struct Index;
  Eigen::MatrixXd V_;
  Eigen::MatrixXi F_;
  Eigen::MatrixXd face_normals_;
  std::vector<int> ring_start_, ring_faces_;  ///< faces around each vertex (CSR)
  double scale_ = 0;
  std::unique_ptr<Index> index_;
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

/// The same fit with colour-aware correspondences: each point (with its colour, k×3, 0..1) is
/// matched to the nearest vertex of `colored` in position-colour space, then gated by distance and
/// normal compatibility against that vertex's normal.
RigidFit fit_rigid(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const Eigen::MatrixXd& colors,
                   const ColoredTarget& colored, const IcpOptions& options, const RigidFit& initial = {});

/// `points` (k×3) moved by `fit`.
Eigen::MatrixXd transformed(const Eigen::MatrixXd& points, const RigidFit& fit);

/// Mean over `points` of the distance to the target, clamped at `gate` (unmatched points count as
/// gate); over the closest `fraction` of them only when it is below 1.
double clamped_mean_distance(const Eigen::MatrixXd& points, const geometry::SurfaceQuery& target, double gate,
                             double fraction = 1.0);

/// The colour at `point` of the target, interpolated from its per-vertex `colors`.
Eigen::RowVector3d interpolated_colour(const geometry::SurfaceQuery& target, const Eigen::MatrixXd& colors,
                                      const geometry::SurfacePoint& point);

/// The same in the joint position-colour space: per point (colour a row of `colors`, 0..1) the
/// distance √(d² + scale²‖c − c'‖²) to its closest target point (colour c' interpolated from
/// `target_colors`, per target vertex), clamped at `gate`; over the closest `fraction` only when
/// it is below 1.
double clamped_mean_joint_distance(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors,
                                   const geometry::SurfaceQuery& target, const Eigen::MatrixXd& target_colors,
                                   double scale, double gate, double fraction = 1.0);

/// The rigid motion best taking `from` onto `to` (rows paired, no scaling; geometry::best_rigid_motion).
RigidFit best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to);

}  // namespace surfcap::align
