#pragma once
// A CGAL::Surface_mesh of triangles copied into the project's Mesh. For the .cpp files that
// already include CGAL (the header itself includes none: the mesh type is a template argument).

#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// The triangles of `surface` (garbage collected first, so its indices are dense) as a Mesh whose
/// vertex and face indices are the surface mesh's.
template <class SurfaceMesh>
Mesh copy_surface_mesh(SurfaceMesh& surface) {
  surface.collect_garbage();
  Mesh mesh;
  mesh.V.resize(static_cast<long>(surface.number_of_vertices()), 3);
  for (auto v : surface.vertices()) {
    const auto& p = surface.point(v);
    mesh.V.row(static_cast<long>(v.idx())) << p.x(), p.y(), p.z();
  }
  mesh.F.resize(static_cast<long>(surface.number_of_faces()), 3);
  for (auto f : surface.faces()) {
    int k = 0;
    for (auto v : surface.vertices_around_face(surface.halfedge(f)))
      mesh.F(static_cast<long>(f.idx()), k++) = static_cast<int>(v.idx());
  }
  return mesh;
}

}  // namespace surfcap::core
