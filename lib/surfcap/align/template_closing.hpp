#pragma once
// The template of an open root reconstruction: the deformation model needs a volume, so each hole
// left open (a floor cut under the feet, a region no camera saw) is closed by a faired surface
// patch (CGAL triangulate_refine_and_fair_hole: a triangulation of the hole refined to the density
// of its rim, then faired for C1 continuity with the surface around it). The reconstruction's own
// vertices and faces stay as they are, first and in their order; the closing surface comes after
// them and is *unobserved*: no data term ever pulls it, it follows the deformation prior.
// Small loose pieces of the reconstruction (spurious blobs, debris: observed_surface.hpp's small
// pieces, which a child's reconstruction leaves unobserved) are not part of the template: nothing
// ties them to the body, so they would float wherever the data terms drag them.

#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::align {

struct TemplateSurface {
  core::Mesh mesh;             ///< the reconstruction, then the closing surface's vertices and faces
  long observed_vertices = 0;  ///< the first this many vertices are the reconstruction's
  long observed_faces = 0;     ///< the first this many faces are the reconstruction's
  long holes = 0;              ///< open holes of the reconstruction (each closed here)
  double largest_hole_perimeter = 0;  ///< metres
  long unfaired_holes = 0;     ///< closed, but the fairing's linear system failed (refined patch kept)
  long loose_pieces = 0;       ///< loose pieces of the reconstruction left out
  /// The reconstruction's vertices left out with them (ascending): template vertex v < observed_vertices
  /// is the reconstruction's vertex v plus the number of these below it.
  std::vector<long> dropped_vertices;
};

/// `reconstruction` (read_reconstruction's output with large holes kept open) without its loose
/// pieces and with every hole closed; a closed reconstruction in one piece is returned as it is.
/// New vertices take the colour and texture coordinates of the nearest rim vertex. Deterministic.
TemplateSurface close_template(core::Mesh reconstruction);

}  // namespace surfcap::align
