#pragma once
// Repair of captured reconstructions: small holes are filled and a few non-manifold edges and
// vertices split, with a warning, so that one bad frame does not stop an alignment; a surface
// beyond the limits stays a bad_input error, except that stages which cope with open surfaces
// keep large holes open. docs/formats.md "Reconstructions" is normative.

#include <filesystem>
#include <optional>
#include <string>

#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// What counts as "small". Beyond any limit the mesh is rejected (bad_input, exit 3).
struct RepairLimits {
  long max_hole_edges = 60;     ///< boundary edges of the largest hole that is filled
  /// Perimeter of the largest hole that is filled, as a share of the bounding-box diagonal
  /// (0.25: a hole ~14 cm across on a 1.8 m actor); keeps "small" independent of the resolution.
  double max_hole_perimeter = 0.25;
  long max_holes = 10;          ///< holes filled per mesh
  long max_non_manifold = 20;   ///< non-manifold edges (MeshCheck) + pinch vertices split per mesh
  long max_debris_faces = 8;    ///< pieces of at most this many faces, beside a larger one, are dropped
  /// Holes beyond max_hole_edges / max_hole_perimeter stay open (counted in RepairReport) instead
  /// of being refused, and any number of small holes is filled: for the stages that cope with
  /// open surfaces (shape histograms, similarity, tree).
  bool keep_large_holes_open = false;
};

/// What repair_mesh did.
struct RepairReport {
  long holes_filled = 0;
  long largest_hole_edges = 0;
  double largest_hole_perimeter = 0;  ///< metres
  long faces_added = 0;             ///< by hole filling
  long non_manifold_edges = 0;      ///< before repair (MeshCheck: more than two faces or inconsistent orientation)
  long non_manifold_vertices = 0;   ///< before repair (pinch points)
  long vertices_duplicated = 0;     ///< to split non-manifold edges and vertices
  long faces_reoriented = 0;        ///< flipped to agree with their neighbours
  long debris_components = 0;       ///< small loose pieces dropped
  long debris_faces = 0;
  long vertices_dropped = 0;        ///< unreferenced after repair (debris, or unused in the file)
  long holes_open = 0;              ///< large holes left open (RepairLimits::keep_large_holes_open)
  long largest_open_hole_edges = 0;
  double largest_open_hole_perimeter = 0;  ///< metres

  bool changed() const;
  /// One line for the warning, e.g. "filled 2 holes (largest 7 edges, 9 faces added)".
  std::string summary() const;
};

/// Vertices where separate fans of faces meet (pinch points; MeshCheck counts only edges).
/// `first`, when given, receives the first such vertex.
long count_pinch_vertices(const Mesh& mesh, long* first = nullptr);

/// Makes `mesh` a closed, edge- and vertex-manifold surface if its defects are within `limits`
/// (with keep_large_holes_open: an edge- and vertex-manifold surface whose large holes stay open):
/// faces are oriented consistently (CGAL orient_polygon_soup, which duplicates the vertices of
/// non-manifold edges and pinch points), each hole is filled by a minimum-weight triangulation of
/// its boundary loop without new vertices (CGAL triangulate_hole, Liepa 2003), small loose debris
/// is dropped and closed pieces turned inside out by reorientation are flipped back. A mesh that is
/// already closed and manifold is returned unchanged. Colours and UVs follow their vertices.
/// bad_input names `source` and `frame` when a limit is exceeded or the result is still not
/// closed and manifold. The input must have passed validate_mesh (finite, indices in range).
RepairReport repair_mesh(Mesh& mesh, const RepairLimits& limits, const std::filesystem::path& source,
                         std::optional<long> frame = std::nullopt);

/// Reads one captured reconstruction (read_mesh tolerating non-manifold, open and zero-area
/// input), then repair_mesh; logs a warning naming the file and frame when it repaired anything
/// (large holes left open are logged at info level: they are data).
Mesh read_reconstruction(const std::filesystem::path& path, std::optional<long> frame = std::nullopt,
                         const RepairLimits& limits = {}, RepairReport* report = nullptr);

}  // namespace surfcap::core
