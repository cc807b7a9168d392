#pragma once
// Convex crease lines of a triangle mesh — a skirt's hem, a sole's rim — and closest-point queries
// on them. Where a thin flap flares, the one-sided dense fit slides the template round its rim onto
// the underside (the surface there is still close, so the residual stays low); matching the
// template's rim to the reconstruction's rim holds it at the edge.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace surfcap::align {

/// Per vertex: the largest dihedral angle (radians; 0 = flat) over its convex edges, i.e. edges
/// where the surface turns away from its outside (a concave edge — an armpit, a skirt meeting the
/// thighs — counts 0). Border and non-manifold edges count 0.
Eigen::VectorXd convex_crease_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// The vertices whose convex crease angle exceeds `min_angle` (radians), ascending.
std::vector<int> convex_crease_vertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_angle);

/// The crease vertices (`crease`, ascending) that lie on a straight stretch of crease: the crease
/// vertices within `radius` of the vertex (itself included, at least 3) spread along one direction,
/// sqrt(λ₂/λ₁) ≤ `max_ratio` for the two largest eigenvalues of their covariance. A hem or a rim
/// is straight at the scale of a hand (`radius` ≈ 8 cm); the crease loop round a small feature (a
/// mitten hand, a fingertip) is not, and such loops are where two reconstructions disagree on
/// whether there is a crease at all. `max_ratio` ≥ 1 keeps every vertex.
std::vector<int> straight_crease_vertices(const Eigen::MatrixXd& V, const std::vector<int>& crease, double radius,
                                          double max_ratio);

/// The convex crease edges of a surface (dihedral angle > `min_angle`), binned for closest-point
/// queries within `reach` (m).
class CreaseLines {
 public:
  CreaseLines(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_angle, double reach);
  long edge_count() const { return static_cast<long>(edges_.size()); }

  /// The closest point to `p` on a crease edge within `max_distance` (≤ reach) whose bisector
  /// (the mean of its two face normals) is within acos(`min_cos`) of `normal`; false when none.
  /// Ties go to the lower edge index (deterministic).
  bool closest(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, double max_distance, double min_cos,
               Eigen::Vector3d& point) const;

 private:
  std::int64_t key(const Eigen::Vector3i& cell) const;
  Eigen::MatrixXd V_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<Eigen::Vector3d> bisectors_;
  double cell_ = 1;
  std::unordered_map<std::int64_t, std::vector<int>> bins_;  ///< edges by midpoint cell
};

}  // namespace surfcap::align
