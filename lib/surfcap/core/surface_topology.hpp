#pragma once
// Topology of a reconstructed surface (holes, pieces, genus) and the closing of its holes for
// volume sampling. Open, multi-piece and higher-genus reconstructions are data, not errors.

#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// One hole: its boundary loop as vertex indices, in the order of the boundary edges (each edge
/// a→b of the loop belongs to a face that runs a→b).
struct BoundaryLoop {
  std::vector<int> vertices;
  double perimeter = 0;  ///< metres
};

/// The boundary loops of an edge-manifold mesh without pinch vertices (read_reconstruction's
/// output), in order of their smallest vertex. Empty for a closed mesh.
std::vector<BoundaryLoop> boundary_loops(const Mesh& mesh);

/// Holes, pieces and genus of an edge-manifold mesh without pinch vertices.
struct SurfaceTopology {
  long holes = 0;                   ///< boundary loops
  long largest_hole_edges = 0;
  double largest_hole_perimeter = 0;  ///< metres
  long components = 0;              ///< pieces connected through edges
  /// Total genus Σ g_i over the pieces, from the Euler characteristic of each: V − E + F = 2 − 2g − b.
  long genus = 0;
};
SurfaceTopology surface_topology(const Mesh& mesh);

/// A closed copy of an edge-manifold mesh for volume sampling: every hole gets one new vertex at
/// the centroid of its boundary loop and a fan of triangles to the loop's edges, oriented like the
/// faces around it. For a planar loop (a surface cut at the floor) the fan covers exactly the flat
/// region the loop bounds, whatever its outline, since the overlaps of a fan cancel with their
/// orientation. Returns the mesh unchanged when it has no hole.
Mesh close_holes(const Mesh& mesh);

}  // namespace surfcap::core
