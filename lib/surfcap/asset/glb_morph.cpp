#include "surfcap/asset/glb_morph.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace surfcap::asset::detail {

std::vector<float> row_major_floats(const Eigen::MatrixXd& matrix) {
  std::vector<float> values(static_cast<std::size_t>(matrix.size()));
  for (long r = 0; r < matrix.rows(); ++r)
    for (long c = 0; c < matrix.cols(); ++c) values[r * matrix.cols() + c] = static_cast<float>(matrix(r, c));
  return values;
}

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

std::vector<float> unit_normals(const std::vector<float>& positions, const Eigen::MatrixXi& faces) {
  const long vertices = static_cast<long>(positions.size() / 3);
  Eigen::MatrixXd V(vertices, 3);
  for (long v = 0; v < vertices; ++v) V.row(v) << positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2];
  const Eigen::MatrixXd N = core::vertex_normals(V, faces);
  std::vector<float> normals(positions.size());
  for (long v = 0; v < vertices; ++v) {
    const bool none = !(N.row(v).squaredNorm() > 0.5);
    for (int k = 0; k < 3; ++k) normals[v * 3 + k] = none ? (k == 1 ? 1.0f : 0.0f) : static_cast<float>(N(v, k));
  }
  return normals;
}

namespace {

/// True when every colour is some k/255 (what mesh IO reads): COLOR_0 restores them exactly.
bool colors_are_bytes(const Eigen::MatrixXd& colors) {
  for (long i = 0; i < colors.size(); ++i) {
    const double c = colors.data()[i];
    if (!(c >= 0 && c <= 1) || std::round(c * 255.0) / 255.0 != c) return false;
  }
  return true;
}

/// COLOR_0: linear colours as normalized UNSIGNED_SHORT VEC4 (alpha 1; VEC4 keeps every element
/// 4-byte aligned, glTF 2.0 §3.6.2.4): 16 bits keep every 8-bit sRGB value distinct.
int add_colors(GlbBuilder& builder, const Eigen::MatrixXd& colors, std::vector<float>* exact_colors) {
  const Eigen::MatrixXd clamped = colors.cwiseMax(0.0).cwiseMin(1.0);
  std::vector<std::uint16_t> rgba(colors.rows() * 4, 65535);
  for (long v = 0; v < colors.rows(); ++v)
    for (int k = 0; k < 3; ++k)
      rgba[v * 4 + k] = static_cast<std::uint16_t>(std::lround(srgb_to_linear(clamped(v, k)) * 65535.0));
  if (exact_colors && !colors_are_bytes(colors)) *exact_colors = row_major_floats(clamped);
  return builder.add_accessor(rgba.data(), colors.rows(), u16, TINYGLTF_TYPE_VEC4, "template", vertex_data, true,
                              exact_codec(8));
}

int add_material(GlbBuilder& builder, const std::vector<std::uint8_t>& texture_png) {
  tinygltf::Material material;
  material.name = "surface";
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  if (!texture_png.empty()) {
    tinygltf::Image image;
    image.bufferView = builder.add_view(texture_png.data(), texture_png.size(), "texture");
    image.mimeType = "image/png";
    builder.model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    builder.model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = 0;
    texture.sampler = 0;
    builder.model.textures.push_back(texture);
    material.pbrMetallicRoughness.baseColorTexture.index = 0;
  }
  builder.model.materials.push_back(material);
  return static_cast<int>(builder.model.materials.size()) - 1;
}

}  // namespace

double morph_position_scale(const GlbBuilder& builder, const core::Mesh& template_mesh,
                            const std::vector<const Eigen::MatrixXd*>& frames) {
  if (!builder.compressed()) return 1;
  const std::vector<float> base = row_major_floats(template_mesh.V);
  float largest = 0;
  for (const Eigen::MatrixXd* frame : frames) {
    const std::vector<float> values = row_major_floats(*frame);
    for (std::size_t i = 0; i < base.size() && i < values.size(); ++i)
      largest = std::max(largest, std::abs(values[i] - base[i]));
  }
  double scale = 1;
  for (int e = 0; e < max_position_scale_exponent && std::lround(largest / scale * 32767.0) > max_quantised_delta; ++e)
    scale *= 2;
  return scale;
}

int add_template_mesh(GlbBuilder& builder, const core::Mesh& mesh, const std::vector<std::uint8_t>& texture_png,
                      const std::string& name, std::vector<float>* exact_colors, double position_scale) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const std::vector<float> positions = row_major_floats(mesh.V);
  std::vector<float> local = positions;
  for (float& x : local) x = static_cast<float>(x / position_scale);  // a power of two: exact
  primitive.attributes["POSITION"] = builder.add_floats(local, TINYGLTF_TYPE_VEC3, "template", vertex_data, true);
  primitive.attributes["NORMAL"] = builder.add_floats(unit_normals(positions, mesh.F), TINYGLTF_TYPE_VEC3, "template",
                                                      vertex_data);
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(mesh.F.size()));
  for (long f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) indices[f * 3 + k] = static_cast<std::uint32_t>(mesh.F(f, k));
  primitive.indices = builder.add_u32(indices, "template", index_data);
  if (mesh.has_colors()) primitive.attributes["COLOR_0"] = add_colors(builder, mesh.colors, exact_colors);
  if (mesh.has_uvs()) {
    // glTF puts the UV origin at the top-left of the image, mesh files at the bottom-left.
    std::vector<float> uvs = row_major_floats(mesh.uvs);
    for (std::size_t i = 1; i < uvs.size(); i += 2) uvs[i] = 1.0f - uvs[i];
    primitive.attributes["TEXCOORD_0"] = builder.add_floats(uvs, TINYGLTF_TYPE_VEC2, "template", vertex_data);
  }
  primitive.material = add_material(builder, mesh.has_uvs() ? texture_png : std::vector<std::uint8_t>{});
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = name;
  gltf_mesh.primitives.push_back(primitive);
  builder.model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.name = name;
  node.mesh = static_cast<int>(builder.model.meshes.size()) - 1;
  if (position_scale != 1) node.scale = {position_scale, position_scale, position_scale};
  builder.model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.name = name;
  scene.nodes.push_back(0);
  builder.model.scenes.push_back(scene);
  builder.model.defaultScene = 0;
  return node.mesh;
}

namespace {

/// The POSITION accessor of one target (world deltas; stored in node units, / `scale`); `delta`
/// becomes what a reader decodes.
int add_position_delta(GlbBuilder& builder, std::vector<float>& delta, double scale) {
  if (builder.compressed()) {
    std::vector<std::int16_t> quantised(delta.size());
    bool fits = true;
    for (std::size_t i = 0; i < delta.size() && fits; ++i) {
      const long q = std::lround(static_cast<float>(delta[i] / scale) * 32767.0f);
      fits = std::abs(q) <= max_quantised_delta;
      quantised[i] = static_cast<std::int16_t>(q);
    }
    if (fits) {  // glTF: c / 32767 node units; × S exact (a power of two)
      for (std::size_t i = 0; i < delta.size(); ++i) delta[i] = static_cast<float>(quantised[i] / 32767.0f * scale);
      return builder.add_normalized(quantised, "morph_targets");
    }
  }
  std::vector<float> local = delta;
  for (float& x : local) x = static_cast<float>(x / scale);
  return builder.add_floats(local, TINYGLTF_TYPE_VEC3, "morph_targets", vertex_data, true, exact_codec(12));
}

/// The NORMAL accessor of one target: float, or in the compressed form normalized BYTE
/// (KHR_mesh_quantization, c / 127) clamped to [−1, 1] (normal deltas reach 2 where a normal
/// turns by more than 60°; shading only, no reader restores them).
int add_normal_delta(GlbBuilder& builder, const std::vector<float>& delta) {
  if (!builder.compressed()) return builder.add_floats(delta, TINYGLTF_TYPE_VEC3, "morph_normals", vertex_data);
  std::vector<std::int8_t> quantised(delta.size());
  for (std::size_t i = 0; i < delta.size(); ++i)
    quantised[i] = static_cast<std::int8_t>(std::lround(std::clamp(delta[i], -1.0f, 1.0f) * 127.0f));
  return builder.add_normalized(quantised, "morph_normals");
}

}  // namespace

int add_morph_targets(GlbBuilder& builder, int mesh, const core::Mesh& template_mesh,
                      const std::vector<Eigen::MatrixXd>& frames, const std::string& prefix,
                      std::vector<std::string>& names, TargetCorrections* corrections, double position_scale) {
  auto& targets = builder.model.meshes[mesh].primitives[0].targets;
  const int first = static_cast<int>(targets.size());
  const std::vector<float> base = row_major_floats(template_mesh.V);
  const std::vector<float> base_normals = unit_normals(base, template_mesh.F);
  std::vector<float> delta(base.size()), stored(base.size()), normal_delta(base.size());
  for (std::size_t t = 0; t < frames.size(); ++t) {
    const std::vector<float> frame = row_major_floats(frames[t]);
    for (std::size_t i = 0; i < base.size(); ++i) delta[i] = frame[i] - base[i];
    const int position = add_position_delta(builder, delta, position_scale);
    for (std::size_t i = 0; i < base.size(); ++i) {
      stored[i] = base[i] + delta[i];  // float32 sum, as viewers and the reader
      if (corrections && !builder.compressed() && stored[i] != frame[i]) {
        corrections->indices.push_back(static_cast<std::uint32_t>(t * base.size() + i));
        corrections->values.push_back(frame[i]);
      }
    }
    // Normals of the frame a viewer shows (the stored one), so a rewrite gives the same bytes.
    const std::vector<float> normals = unit_normals(stored, template_mesh.F);
    for (std::size_t i = 0; i < base.size(); ++i) normal_delta[i] = normals[i] - base_normals[i];
    const int normal = add_normal_delta(builder, normal_delta);
    targets.push_back({{"POSITION", position}, {"NORMAL", normal}});
    char number[24];
    std::snprintf(number, sizeof number, "%04zu", t);
    names.push_back(prefix + number);
  }
  return first;
}

void finish_morph_targets(GlbBuilder& builder, int mesh, const std::vector<std::string>& target_names) {
  auto& gltf_mesh = builder.model.meshes[mesh];
  gltf_mesh.weights.assign(target_names.size(), 0.0);
  tinygltf::Value::Array names;
  for (const auto& name : target_names) names.emplace_back(name);
  // extras.targetNames: the de-facto convention Blender and three.js read shape-key names from.
  if (!names.empty()) gltf_mesh.extras = tinygltf::Value(tinygltf::Value::Object{{"targetNames", tinygltf::Value(names)}});
}

namespace {
int add_channel(tinygltf::Animation& animation, int input, int output, const std::string& path) {
  tinygltf::AnimationSampler sampler;
  sampler.input = input;
  sampler.output = output;
  sampler.interpolation = "LINEAR";
  animation.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
  channel.target_node = 0;
  channel.target_path = path;
  animation.channels.push_back(channel);
  return channel.sampler;
}
}  // namespace

int add_morph_animation(GlbBuilder& builder, int first_target, int frames, int total_targets, double fps,
                        const std::vector<core::RootMotion>* root, const std::string& name) {
  if (frames <= 0) return -1;
  std::vector<float> times(frames), weights(static_cast<std::size_t>(frames) * total_targets, 0.0f);
  for (int t = 0; t < frames; ++t) {
    times[t] = static_cast<float>(t / fps);
    weights[static_cast<std::size_t>(t) * total_targets + first_target + t] = 1.0f;
  }
  tinygltf::Animation animation;
  animation.name = name;
  const int input = builder.add_floats(times, TINYGLTF_TYPE_SCALAR, "animations", no_target, true);
  add_channel(animation, input, builder.add_floats(weights, TINYGLTF_TYPE_SCALAR, "animations", no_target, false,
                                                   exact_codec(4)), "weights");
  if (root) {
    std::vector<float> translation, rotation;
    float previous_w = 1, previous_y = 0;
    for (const core::RootMotion& r : *root) {
      translation.insert(translation.end(), {float(r.x), float(r.y), float(r.z)});
      float y = static_cast<float>(std::sin(r.heading / 2)), w = static_cast<float>(std::cos(r.heading / 2));
      if (y * previous_y + w * previous_w < 0) y = -y, w = -w;  // same hemisphere: slerp takes the short way
      rotation.insert(rotation.end(), {0.0f, y, 0.0f, w});
      previous_y = y, previous_w = w;
    }
    add_channel(animation, input, builder.add_floats(translation, TINYGLTF_TYPE_VEC3, "animations", no_target, false,
                                                     exact_codec(12)), "translation");
    add_channel(animation, input, builder.add_floats(rotation, TINYGLTF_TYPE_VEC4, "animations", no_target, false,
                                                     exact_codec(16)), "rotation");
  }
  builder.model.animations.push_back(animation);
  return static_cast<int>(builder.model.animations.size()) - 1;
}

}  // namespace surfcap::asset::detail
