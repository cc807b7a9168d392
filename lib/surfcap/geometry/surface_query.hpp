#pragma once
// Queries against a fixed triangle surface (CGAL AABB tree, kept inside surface_query.cpp):
// closest points (for ICP and dense fitting) and first hits of rays (back-projection of image
// features onto the visible surface).

#include <Eigen/Core>
#include <memory>
#include <optional>

namespace surfcap::geometry {

/// A point on the surface: the face it lies on, its barycentric coordinates and position.
struct SurfacePoint {
  long face = -1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
  double distance = 0;  ///< from the query point (closest point) or along the ray (first hit), metres
};

class SurfaceQuery {
 public:
  /// Builds the tree over the faces of (V n×3, F m×3); degenerate faces are skipped.
  SurfaceQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~SurfaceQuery();
  SurfaceQuery(SurfaceQuery&&) noexcept;
  SurfaceQuery& operator=(SurfaceQuery&&) noexcept;

  /// The closest surface point to `point`. Thread-safe (const queries on a built tree).
  SurfacePoint closest_point(const Eigen::Vector3d& point) const;
  /// closest_point(point) when it lies within `max_distance` — bit for bit the same point, face and
  /// distance — and nullopt otherwise (or possibly a point at most 1e-9 relative beyond the bound:
  /// callers keep their distance test). Prunes the search to the bound: cheap when nothing is near.
  std::optional<SurfacePoint> closest_point_within(const Eigen::Vector3d& point, double max_distance) const;
  /// The first intersection of the ray origin + s·direction, s > 0; nullopt if it misses.
  std::optional<SurfacePoint> first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;

  /// Unit normal of face f (counter-clockwise seen from outside).
  Eigen::Vector3d face_normal(long f) const { return face_normals_.row(f).transpose(); }
  const Eigen::MatrixXd& face_normals() const { return face_normals_; }
  const Eigen::MatrixXd& vertices() const { return V_; }
  const Eigen::MatrixXi& faces() const { return F_; }

 private:
  /// The SurfacePoint at `position` on primitive `triangle`, its distance from `point`.
  SurfacePoint surface_point(const Eigen::Vector3d& point, const Eigen::Vector3d& position, std::size_t triangle) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  Eigen::MatrixXd V_;
  Eigen::MatrixXi F_;
  Eigen::MatrixXd face_normals_;
};

/// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection, §5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

/// Barycentric coordinates of p's projection onto triangle (a, b, c) (summing to 1).
Eigen::Vector3d barycentric_coordinates(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& c);

}  // namespace surfcap::geometry
