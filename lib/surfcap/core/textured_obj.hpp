#pragma once
// Textured OBJ frames as studios deliver them: OBJ + MTL + texture image, per-corner texture
// coordinates that differ across UV seams, often with the seam vertices' positions duplicated.

#include <filesystem>
#include <optional>
#include <string>

#include "surfcap/core/mesh.hpp"

namespace surfcap::core {

/// True when an OBJ text names a material library and uses a material (mtllib + usemtl lines):
/// read_mesh then reads it through read_textured_obj.
bool obj_uses_materials(const std::string& obj_text);

/// Reads an OBJ whose colours come from its materials. Vertices at the same position (bit for
/// bit) are welded into one, keeping the first in file order, so the seams of a UV atlas do not
/// cut the surface. Each face corner takes the colour of its material: the diffuse texture
/// (map_Kd, a PNG, sampled bilinearly at the corner's texture coordinate, values as stored, i.e.
/// sRGB; repeat wrapping unless "-clamp on") or else the diffuse colour Kd; a vertex gets the mean
/// of its corners' colours. The mesh has colours and no UVs (a welded vertex has several).
/// Material libraries and textures are named relative to the file that names them and must stay
/// inside its folder. Polygons are triangulated as fans. bad_input names the OBJ, MTL or image
/// and `frame`; the OBJ must have passed precheck_mesh_file.
Mesh read_textured_obj(const std::filesystem::path& path, const std::string& obj_text,
                       std::optional<long> frame = std::nullopt);

}  // namespace surfcap::core
