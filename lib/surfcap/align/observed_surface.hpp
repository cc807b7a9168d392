#pragma once
// Where a reconstruction shows real surface. A hole left open (a floor cut, a region no camera
// saw) is no evidence of where the surface is: a closest point on the hole's rim is not a
// correspondence, only the nearest thing to one. Nor is a small loose piece beside the body (a
// spurious blob of the reconstruction). Every correspondence source of the alignment and its
// checks ask this one object whether a point of the child's reconstruction is observed: on a piece
// of at least kSmallPieceShare of the faces, and neither on a hole's boundary nor within
// kBoundaryBandEdges of the reconstruction's mean edge of it (along its edges). A closed
// reconstruction in one piece is observed everywhere.

#include <Eigen/Core>

#include <vector>

#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

/// The band around a hole's boundary with no correspondence, in mean edge lengths of the
/// reconstruction: the rim's vertices and its faces' interior, where a reconstruction's cut
/// edge is least reliable.
inline constexpr double kBoundaryBandEdges = 1.5;
/// A piece of the reconstruction with fewer than this share of its faces is not observed surface.
inline constexpr double kSmallPieceShare = 0.02;

/// Per vertex of a surface with n vertices and faces F, the share of the faces in its piece (pieces
/// connected through shared vertices); `pieces_below` receives the number of pieces under `share`.
Eigen::VectorXd piece_shares(long n, const Eigen::MatrixXi& F, long& pieces_below, double share);

class ObservedSurface {
 public:
  /// Of the reconstruction (V n×3, F m×3; edge-manifold, as read_reconstruction returns it).
  ObservedSurface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  /// False when every point is observed (closed, one piece or pieces all large).
  bool partial() const { return boundary_distance_.size() > 0; }
  long holes() const { return holes_; }  ///< boundary loops
  double largest_hole_perimeter() const { return largest_hole_perimeter_; }  ///< metres
  long small_pieces() const { return small_pieces_; }
  /// Is this point of the reconstruction (face + barycentric) observed? (Boundary distance
  /// interpolated over its face.)
  bool observed(const geometry::SurfacePoint& point) const;
  /// Is reconstruction vertex i observed?
  bool observed_vertex(long i) const { return !partial() || boundary_distance_(i) >= band_; }

 private:
  long holes_ = 0;
  double largest_hole_perimeter_ = 0;
  long small_pieces_ = 0;
  Eigen::MatrixXi F_;
  /// Per vertex: distance to the nearest hole boundary along the edges, capped at the band; 0 on
  /// a small piece. Empty when everything is observed.
  Eigen::VectorXd boundary_distance_;
  double band_ = 0;  ///< metres
};

}  // namespace surfcap::align
