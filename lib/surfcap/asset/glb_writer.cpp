// character.glb and animation.glb: standard glTF content (glb_morph) + the SURFCAP_motion_graph
// extension (glb_extension_write), one buffer, written atomically.
#include <chrono>

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/asset/glb_extension.hpp"
#include "surfcap/asset/glb_morph.hpp"
#include "surfcap/asset/vertex_order.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/version.hpp"

namespace surfcap::asset {
namespace {
using namespace detail;

std::string generator_of(const GlbWriteOptions& options) {
  return options.generator.empty() ? "surfcap " + std::string(core::version()) : options.generator;
}

void check_template(const core::Mesh& mesh) {
  if (mesh.vertex_count() == 0 || mesh.face_count() == 0 || mesh.V.cols() != 3 || mesh.F.cols() != 3)
    throw core::internal_error("cannot export an empty template mesh");
  if (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.vertex_count())
    throw core::internal_error("the template mesh has face indices out of range");
}

/// The capture's frame rate where clients read metadata: scene extras (Blender: the scene's
/// custom properties) — glTF itself keys animations in seconds.
void set_scene_timing(GlbBuilder& builder, double fps, long frames) {
  builder.model.scenes.at(0).extras = tinygltf::Value(tinygltf::Value::Object{
      {"fps", tinygltf::Value(fps)}, {"frames", tinygltf::Value(static_cast<int>(frames))}});
}

/// Every sequence as morph targets + an animation; returns the extension's "sequences".
core::Json add_sequences(GlbBuilder& builder, int mesh, const Character& character, double position_scale) {
  std::vector<std::string> names;
  std::vector<int> first_targets;
  core::Json sequences = core::Json::array();
  for (const core::AlignedSequence& sequence : character.sequences) {
    for (const Eigen::MatrixXd& frame : sequence.frames)
      if (frame.rows() != character.vertex_count() || frame.cols() != 3)
        throw core::internal_error("sequence '" + sequence.name + "' has frames of another vertex count than the template");
    if (sequence.root_motion.size() != sequence.frames.size())
      throw core::internal_error("sequence '" + sequence.name + "' needs one root motion per frame");
    TargetCorrections corrections;
    first_targets.push_back(
        add_morph_targets(builder, mesh, character.template_mesh, sequence.frames, sequence.name + "/", names,
                          &corrections, position_scale));
    core::Json entry = {{"name", sequence.name}, {"frames", sequence.frame_count()}, {"firstTarget", first_targets.back()}};
    std::vector<float> root;
    for (const core::RootMotion& r : sequence.root_motion)
      root.insert(root.end(), {float(r.x), float(r.y), float(r.z), float(r.heading)});
    if (const int accessor = builder.add_floats(root, TINYGLTF_TYPE_VEC4, "sequences", no_target, false, exact_codec(16));
        accessor >= 0)
      entry["rootMotion"] = accessor;
    if (!corrections.indices.empty())
      entry["corrections"] = {{"indices", builder.add_u32(corrections.indices, "sequences", no_target, exact_codec(4))},
                              {"values", builder.add_floats(corrections.values, TINYGLTF_TYPE_SCALAR, "sequences",
                                                            no_target, false, exact_codec(4))}};
    sequences.push_back(entry);
  }
  finish_morph_targets(builder, mesh, names);
  for (std::size_t s = 0; s < character.sequences.size(); ++s) {
    const auto& sequence = character.sequences[s];
    const int animation = add_morph_animation(builder, first_targets[s], sequence.frame_count(),
                                              static_cast<int>(names.size()), character.fps, &sequence.root_motion,
                                              sequence.name);
    if (animation >= 0) sequences[s]["animation"] = animation;
  }
  return sequences;
}

core::Json extension_json(GlbBuilder& builder, int mesh, const Character& character,
                          const std::vector<float>& exact_colors, double position_scale) {
  core::Json extension = {{"version", motion_graph_extension_version}, {"name", character.name},
                          {"fps", character.fps}, {"units", character.units}, {"mesh", mesh}, {"node", 0},
                          {"provenance", character.provenance}};
  extension["sequences"] = add_sequences(builder, mesh, character, position_scale);
  if (character.template_mesh.has_uvs())  // exact, in the mesh files' convention (v up)
    extension["template"]["uvs"] = builder.add_floats(row_major_floats(character.template_mesh.uvs),
                                                      TINYGLTF_TYPE_VEC2, "template", no_target, false, exact_codec(8));
  if (!exact_colors.empty())  // sRGB, exact, when COLOR_0 (linear, 16 bits) cannot restore them
    extension["template"]["colors"] =
        builder.add_floats(exact_colors, TINYGLTF_TYPE_VEC3, "template", no_target, false, exact_codec(12));
  extension["spaces"] = spaces_json(builder, character);
  extension["transitions"] = transitions_json(builder, character);
  if (character.parts) extension["parts"] = parts_json(builder, character);
  return extension;
}

GlbSummary summarise(const GlbBuilder& builder, const std::string& glb) {
  GlbSummary summary;
  summary.file_bytes = glb.size();
  summary.buffer_bytes = builder.bytes_by_kind();
  summary.json_bytes = static_cast<std::uint8_t>(glb[12]) | static_cast<std::uint8_t>(glb[13]) << 8 |
                       static_cast<std::uint8_t>(glb[14]) << 16 | static_cast<std::size_t>(static_cast<std::uint8_t>(glb[15])) << 24;
  summary.accessors = static_cast<long>(builder.model.accessors.size());
  summary.compressed = builder.compressed();
  summary.animations = static_cast<long>(builder.model.animations.size());
  summary.morph_targets = static_cast<long>(builder.model.meshes.at(0).primitives.at(0).targets.size());
  return summary;
}

/// The file's content: `character`, in the compressed form with its vertices in the codec's order.
std::string character_bytes(const Character& character, const std::vector<std::uint32_t>& vertex_order,
                            const GlbWriteOptions& options, GlbSummary* summary) {
  GlbBuilder builder(generator_of(options), options.compress);
  std::vector<const Eigen::MatrixXd*> all_frames;
  for (const auto& sequence : character.sequences)
    for (const Eigen::MatrixXd& frame : sequence.frames) all_frames.push_back(&frame);
  const double scale = morph_position_scale(builder, character.template_mesh, all_frames);
  std::vector<float> exact_colors;
  const int mesh = add_template_mesh(builder, character.template_mesh, character.texture_png, character.name,
                                     &exact_colors, scale);
  set_scene_timing(builder, character.fps, static_cast<long>(all_frames.size()));
  core::Json extension = extension_json(builder, mesh, character, exact_colors, scale);
  if (!vertex_order.empty()) extension["vertexOrder"] = builder.add_u32(vertex_order, "template", no_target, exact_codec(4));
  std::string glb = builder.finish({{motion_graph_extension, extension}});
  if (summary) *summary = summarise(builder, glb);
  return glb;
}

}  // namespace

std::string character_glb_bytes(const Character& character, const GlbWriteOptions& options, GlbSummary* summary) {
  check_template(character.template_mesh);
  if (!(character.fps > 0)) throw core::internal_error("cannot export a character with fps " + std::to_string(character.fps));
  if (!options.compress) return character_bytes(character, {}, options, summary);
  const std::vector<std::uint32_t> order = compression_vertex_order(character.template_mesh.F, character.vertex_count());
  return character_bytes(reorder_vertices(character, order), order, options, summary);
}

GlbSummary write_character_glb(const std::filesystem::path& path, const Character& character,
                               const GlbWriteOptions& options) {
  GlbSummary summary;
  const std::string glb = character_glb_bytes(character, options, &summary);
  core::write_file_atomically(path, glb);
  return summary;
}

GlbSummary write_animation_glb(const std::filesystem::path& path, const core::Mesh& template_mesh,
                               const std::vector<Eigen::MatrixXd>& centred_frames,
                               const std::vector<core::RootMotion>& root_motion, double fps, const std::string& name,
                               const GlbWriteOptions& options) {
  check_template(template_mesh);
  if (!(fps > 0)) throw core::internal_error("an animation needs fps > 0");
  if (root_motion.size() != centred_frames.size()) throw core::internal_error("an animation needs one root motion per frame");
  for (const Eigen::MatrixXd& frame : centred_frames)
    if (frame.rows() != template_mesh.vertex_count() || frame.cols() != 3)
      throw core::internal_error("animation '" + name + "' has frames of another vertex count than the template");
  GlbBuilder builder(generator_of(options), options.compress);
  std::vector<const Eigen::MatrixXd*> frames;
  for (const Eigen::MatrixXd& frame : centred_frames) frames.push_back(&frame);
  const double scale = morph_position_scale(builder, template_mesh, frames);
  const int mesh = add_template_mesh(builder, template_mesh, {}, name, nullptr, scale);
  set_scene_timing(builder, fps, static_cast<long>(centred_frames.size()));
  std::vector<std::string> names;
  const int first = add_morph_targets(builder, mesh, template_mesh, centred_frames, name + "/", names, nullptr, scale);
  finish_morph_targets(builder, mesh, names);
  add_morph_animation(builder, first, static_cast<int>(centred_frames.size()), static_cast<int>(names.size()), fps,
                      &root_motion, name);
  const std::string glb = builder.finish(core::Json::object());
  core::write_file_atomically(path, glb);
  return summarise(builder, glb);
}

}  // namespace surfcap::asset
