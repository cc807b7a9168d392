// Reading character.glb: the container checked first (glb_container), the glTF structures
// through tinygltf, the SURFCAP_motion_graph extension from the exact JSON (glb_extension_read).
#include <algorithm>
#include <cmath>
#include <limits>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/asset/glb_container.hpp"
#include "surfcap/asset/glb_extension.hpp"
#include "surfcap/asset/glb_meshopt.hpp"
#include "surfcap/asset/glb_morph.hpp"
#include "surfcap/asset/vertex_order.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/atomic_file.hpp"

namespace surfcap::asset {
namespace {
using namespace detail;

const tinygltf::Primitive& template_primitive(const tinygltf::Model& model, int mesh, const std::filesystem::path& source) {
  if (mesh < 0 || mesh >= static_cast<int>(model.meshes.size()) || model.meshes[mesh].primitives.empty())
    throw core::bad_input(source, "the extension's mesh " + std::to_string(mesh) + " does not exist");
  const tinygltf::Primitive& primitive = model.meshes[mesh].primitives[0];
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES || primitive.indices < 0 || !primitive.attributes.count("POSITION"))
    throw core::bad_input(source, "the template mesh is not an indexed triangle mesh with POSITION");
  return primitive;
}

Eigen::MatrixXd matrix_of(const std::vector<float>& values, long rows, long cols) {
  Eigen::MatrixXd matrix(rows, cols);
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c) matrix(r, c) = values[r * cols + c];
  return matrix;
}

std::vector<std::uint8_t> texture_bytes(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                        const GlbAccessors& accessors) {
  if (primitive.material < 0 || primitive.material >= static_cast<int>(model.materials.size())) return {};
  const int texture = model.materials[primitive.material].pbrMetallicRoughness.baseColorTexture.index;
  if (texture < 0) return {};
  if (texture >= static_cast<int>(model.textures.size()) || model.textures[texture].source < 0 ||
      model.textures[texture].source >= static_cast<int>(model.images.size()))
    throw core::bad_input(accessors.source(), "the base colour texture does not exist");
  const std::string_view png = accessors.view_bytes(model.images[model.textures[texture].source].bufferView, "texture");
  return {png.begin(), png.end()};
}

/// Version 1 stored the sRGB values themselves in COLOR_0 (bytes, or float VEC3).
Eigen::MatrixXd srgb_color_0(const GlbAccessors& accessors, int index, long vertices) {
  Eigen::MatrixXd colors(vertices, 3);
  if (accessors.accessor(index, "COLOR_0").componentType == u8) {
    const auto rgba = accessors.read<std::uint8_t>(index, u8, TINYGLTF_TYPE_VEC4, vertices, "COLOR_0", true);
    for (long v = 0; v < vertices; ++v)
      for (int k = 0; k < 3; ++k) colors(v, k) = rgba[v * 4 + k] / 255.0;
    return colors;
  }
  return matrix_of(accessors.read<float>(index, f32, TINYGLTF_TYPE_VEC3, vertices, "COLOR_0"), vertices, 3);
}

/// Version 2: linear COLOR_0 (normalized UNSIGNED_SHORT VEC4) back to the captured 8-bit sRGB.
Eigen::MatrixXd linear_color_0(const GlbAccessors& accessors, int index, long vertices) {
  const auto rgba = accessors.read<std::uint16_t>(index, u16, TINYGLTF_TYPE_VEC4, vertices, "COLOR_0", true);
  Eigen::MatrixXd colors(vertices, 3);
  for (long v = 0; v < vertices; ++v)
    for (int k = 0; k < 3; ++k) colors(v, k) = std::round(linear_to_srgb(rgba[v * 4 + k] / 65535.0) * 255.0) / 255.0;
  return colors;
}

/// The template node's scale S (glb_morph.hpp add_template_mesh): 1, or a uniform power of two
/// in [2, 2^8] by which POSITION and the morph targets are multiplied.
double node_scale(const tinygltf::Model& model, const core::Json& extension, const std::filesystem::path& source) {
  const long node = extension.contains("node") ? integer_field(extension, "node", source) : 0;
  if (node < 0 || node >= static_cast<long>(model.nodes.size()))
    throw core::bad_input(source, "the extension's node does not exist");
  const std::vector<double>& scale = model.nodes[static_cast<std::size_t>(node)].scale;
  if (scale.empty()) return 1;
  int exponent = 0;
  const bool power_of_two = scale.size() == 3 && std::frexp(scale[0], &exponent) == 0.5;
  if (!power_of_two || scale[1] != scale[0] || scale[2] != scale[0] || exponent < 1 ||
      exponent > max_position_scale_exponent + 1)
    throw core::bad_input(source, "the template node's scale is not a uniform power of two in [1, 256]");
  return scale[0];
}

void read_template(const tinygltf::Model& model, const GlbAccessors& accessors, const core::Json& extension,
                   int version, double scale, Character& character) {
  const auto& source = accessors.source();
  const tinygltf::Primitive& primitive = template_primitive(model, integer_field(extension, "mesh", source), source);
  core::Mesh& mesh = character.template_mesh;
  const int position = primitive.attributes.at("POSITION");
  const long vertices = accessors.count(position, "template POSITION");
  mesh.V = matrix_of(accessors.read<float>(position, f32, TINYGLTF_TYPE_VEC3, vertices, "template POSITION"), vertices, 3) *
           scale;
  const std::vector<std::uint32_t> indices =
      accessors.read<std::uint32_t>(primitive.indices, u32, TINYGLTF_TYPE_SCALAR, -1, "template indices");
  if (indices.size() % 3 != 0) throw core::bad_input(source, "template indices are not whole triangles");
  mesh.F.resize(static_cast<long>(indices.size() / 3), 3);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= static_cast<std::uint64_t>(vertices)) throw core::bad_input(source, "template index out of range");
    mesh.F.data()[(i % 3) * mesh.F.rows() + i / 3] = static_cast<int>(indices[i]);
  }
  const core::Json no_template = core::Json::object();
  const core::Json& exact = extension.contains("template") ? extension["template"] : no_template;
  if (const auto it = primitive.attributes.find("COLOR_0"); it != primitive.attributes.end()) {
    if (version < 2) mesh.colors = srgb_color_0(accessors, it->second, vertices);
    else if (exact.contains("colors"))
      mesh.colors = matrix_of(accessors.read<float>(integer_field(exact, "colors", source), f32, TINYGLTF_TYPE_VEC3,
                                                    vertices, "template colors"), vertices, 3);
    else mesh.colors = linear_color_0(accessors, it->second, vertices);
  }
  if (exact.contains("uvs"))
    mesh.uvs = matrix_of(accessors.read<float>(integer_field(exact, "uvs", source), f32,
                                               TINYGLTF_TYPE_VEC2, vertices, "template uvs"), vertices, 2);
  character.texture_png = texture_bytes(model, primitive, accessors);
  core::MeshRequirements lenient;
  lenient.allow_non_manifold = lenient.allow_zero_area_faces = true;
  core::validate_mesh(mesh, lenient, source);
}

/// A morph target's POSITION: float, or normalized SHORT (KHR_mesh_quantization, c / 32767),
/// times the node scale.
std::vector<float> position_delta(const GlbAccessors& accessors, int index, long vertices, double scale,
                                  const std::string& what) {
  std::vector<float> delta;
  if (accessors.accessor(index, what).componentType != i16) {
    delta = accessors.read<float>(index, f32, TINYGLTF_TYPE_VEC3, vertices, what);
  } else {
    const auto quantised = accessors.read<std::int16_t>(index, i16, TINYGLTF_TYPE_VEC3, vertices, what, true);
    delta.resize(quantised.size());
    for (std::size_t i = 0; i < delta.size(); ++i) delta[i] = std::max(quantised[i] / 32767.0f, -1.0f);
  }
  for (float& x : delta) x = static_cast<float>(x * scale);
  return delta;
}

/// Frames = template + morph target in float32, then the exact corrections (glb_morph.hpp).
void read_sequence(const tinygltf::Primitive& primitive, const GlbAccessors& accessors, const core::Json& entry,
                   const std::vector<float>& base, double scale, Character& character) {
  const auto& source = accessors.source();
  core::AlignedSequence sequence;
  sequence.name = core::get_field<std::string>(entry, "name", source);
  const long frames = integer_field(entry, "frames", source), first = entry.contains("firstTarget") ? integer_field(entry, "firstTarget", source) : 0;
  if (frames < 0 || first < 0 || first + frames > static_cast<long>(primitive.targets.size()))
    throw core::bad_input(source, "sequence '" + sequence.name + "' refers to morph targets that do not exist");
  const long vertices = static_cast<long>(base.size() / 3);
  for (long t = 0; t < frames; ++t) {
    const auto& target = primitive.targets[first + t];
    const auto it = target.find("POSITION");
    if (it == target.end()) throw core::bad_input(source, "a morph target of '" + sequence.name + "' has no POSITION");
    const auto delta = position_delta(accessors, it->second, vertices, scale, "morph target of '" + sequence.name + "'");
    Eigen::MatrixXd frame(vertices, 3);
    for (long v = 0; v < vertices; ++v)
      for (int k = 0; k < 3; ++k) frame(v, k) = base[v * 3 + k] + delta[v * 3 + k];  // float32 sum, as viewers
    sequence.frames.push_back(std::move(frame));
  }
  if (entry.contains("corrections")) {
    const core::Json& c = entry["corrections"];
    const auto indices = accessors.read<std::uint32_t>(integer_field(c, "indices", source), u32,
                                                       TINYGLTF_TYPE_SCALAR, -1, "corrections");
    const auto exact = accessors.read<float>(integer_field(c, "values", source), f32, TINYGLTF_TYPE_SCALAR,
                                             static_cast<long>(indices.size()), "corrections");
    for (std::size_t i = 0; i < indices.size(); ++i) {
      if (indices[i] >= static_cast<std::uint64_t>(frames) * base.size())
        throw core::bad_input(source, "a correction of '" + sequence.name + "' is out of range");
      const std::size_t t = indices[i] / base.size(), component = indices[i] % base.size();
      sequence.frames[t](static_cast<long>(component / 3), static_cast<long>(component % 3)) = exact[i];
    }
  }
  if (frames > 0) {
    const auto root = accessors.read<float>(integer_field(entry, "rootMotion", source), f32, TINYGLTF_TYPE_VEC4,
                                            frames, "root motion of '" + sequence.name + "'");
    for (long t = 0; t < frames; ++t)
      sequence.root_motion.push_back({root[4 * t], root[4 * t + 1], root[4 * t + 2], root[4 * t + 3]});
  }
  character.sequences.push_back(std::move(sequence));
}

Character read_character(const tinygltf::Model& model, const GlbAccessors& accessors, const core::Json& extension,
                         int version) {
  const auto& source = accessors.source();
  Character character;
  character.name = core::get_field<std::string>(extension, "name", source);
  character.fps = core::get_field<double>(extension, "fps", source);
  if (!(character.fps > 0 && character.fps <= core::kMaxFps))
    throw core::bad_input(source, "fps must be in (0, " + std::to_string(static_cast<int>(core::kMaxFps)) + "]");
  character.units = extension.value("units", std::string("m"));
  if (extension.contains("provenance")) character.provenance = extension["provenance"];
  const double scale = node_scale(model, extension, source);
  read_template(model, accessors, extension, version, scale, character);
  const tinygltf::Primitive& primitive = template_primitive(model, integer_field(extension, "mesh", source), source);
  std::vector<float> base(static_cast<std::size_t>(character.template_mesh.V.size()));
  for (long v = 0; v < character.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k) base[v * 3 + k] = static_cast<float>(character.template_mesh.V(v, k));
  if (extension.contains("sequences"))
    for (const core::Json& entry : extension["sequences"])
      read_sequence(primitive, accessors, entry, base, scale, character);
  read_spaces(extension, accessors, character);
  read_transitions(extension, accessors, character);
  read_parts(extension, accessors, character);
  if (const long order = extension.contains("vertexOrder") ? integer_field(extension, "vertexOrder", source) : -1; order >= 0) {
    const long vertices = character.vertex_count();
    return reorder_vertices(character, inverse_order(accessors.read<std::uint32_t>(order, u32, TINYGLTF_TYPE_SCALAR,
                                                                                   vertices, "vertexOrder"),
                                                     vertices, source));
  }
  return character;
}

}  // namespace

Character parse_character_glb(std::string_view bytes, const std::filesystem::path& source) {
  const GlbChunks chunks = unpack_glb(bytes, source);
  try {
    const core::Json json = core::parse_json_text(chunks.json, source);
    const auto extensions = json.find("extensions");
    if (extensions == json.end() || !extensions->is_object() || !extensions->contains(motion_graph_extension))
      throw core::bad_input(source, std::string("no ") + motion_graph_extension + " extension: not a surfcap character");
    const core::Json& extension = (*extensions)[motion_graph_extension];
    const int version = integer_field(extension, "version", source);
    if (version < 1 || version > motion_graph_extension_version)
      throw core::bad_input(source, std::string(motion_graph_extension) + " version " + std::to_string(version) +
                                        " (this surfcap reads 1.." + std::to_string(motion_graph_extension_version) +
                                        "): written by a newer surfcap?");
    // The compressed form: its views decoded first, then checked like any other file.
    const std::string decoded = decode_meshopt_glb(bytes, source);
    const std::string_view plain = decoded.empty() ? bytes : std::string_view(decoded);
    const tinygltf::Model model = load_gltf(plain, source);
    const GlbAccessors accessors(model, unpack_glb(plain, source).bin, source);
    return read_character(model, accessors, extension, version);
  } catch (const nlohmann::json::exception& e) {
    throw core::bad_input(source, std::string("malformed glTF JSON: ") + e.what());
  } catch (const std::out_of_range& e) {
    throw core::bad_input(source, std::string("malformed glTF: ") + e.what());
  }
}

Character read_character_glb(const std::filesystem::path& path) {
  const std::string bytes = core::read_file(path);
  return parse_character_glb(bytes, path);
}

}  // namespace surfcap::asset
