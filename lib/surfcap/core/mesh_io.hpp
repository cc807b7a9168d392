#pragma once
// Mesh files through OpenMesh: OBJ, PLY (binary and ASCII), OFF, with per-vertex colours and UVs;
// textured OBJ (MTL + PNG) through core/textured_obj.

#include <filesystem>
#include <optional>

#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// Reads a mesh (format from the extension: .obj .ply .off), triangulating polygons as fans,
/// and validates it against `requirements`. An OBJ that uses materials (mtllib + usemtl) is read
/// by read_textured_obj: welded by position, colours from its textures (core/textured_obj.hpp).
/// Errors name `path` and `frame`: io_error (4) when
/// the file cannot be read, bad_input (3) when it is truncated, corrupt or invalid.
Mesh read_mesh(const std::filesystem::path& path, const MeshRequirements& requirements = {},
               std::optional<long> frame = std::nullopt);

struct MeshWriteOptions {
  bool binary = true;        ///< PLY only: binary little-endian (else ASCII)
  bool write_colors = true;  ///< if the mesh has colours
  bool write_uvs = true;     ///< if the mesh has UVs
};

/// Writes atomically (format from the extension). The mesh must be edge-manifold: OpenMesh's
/// halfedge structure cannot hold anything else (internal error otherwise).
void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& options = {});

}  // namespace surfcap::core
