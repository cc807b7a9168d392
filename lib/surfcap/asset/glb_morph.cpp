#include "surfcap/asset/glb_morph.hpp"

#include <cmath>
#include <cstdio>

namespace surfcap::asset::detail {

std::vector<float> row_major_floats(const Eigen::MatrixXd& matrix) {
  std::vector<float> values(static_cast<std::size_t>(matrix.size()));
  for (long r = 0; r < matrix.rows(); ++r)
    for (long c = 0; c < matrix.cols(); ++c) values[r * matrix.cols() + c] = static_cast<float>(matrix(r, c));
  return values;
}

namespace {

/// True when every colour is some k/255: stored exactly as normalised bytes (what mesh IO reads).
bool colors_are_bytes(const Eigen::MatrixXd& colors) {
  for (long i = 0; i < colors.size(); ++i) {
    const double c = colors.data()[i];
    if (!(c >= 0 && c <= 1) || std::round(c * 255.0) / 255.0 != c) return false;
  }
  return true;
}

int add_colors(GlbBuilder& builder, const Eigen::MatrixXd& colors) {
  if (colors_are_bytes(colors)) {
    // VEC4 keeps every element 4-byte aligned as vertex attributes must be (glTF 2.0 §3.6.2.4).
    std::vector<std::uint8_t> rgba(colors.rows() * 4, 255);
    for (long v = 0; v < colors.rows(); ++v)
      for (int k = 0; k < 3; ++k) rgba[v * 4 + k] = static_cast<std::uint8_t>(std::lround(colors(v, k) * 255.0));
    return builder.add_accessor(rgba.data(), colors.rows(), u8, TINYGLTF_TYPE_VEC4, "template", vertex_data, true);
  }
  Eigen::MatrixXd clamped = colors.cwiseMax(0.0).cwiseMin(1.0);
  return builder.add_floats(row_major_floats(clamped), TINYGLTF_TYPE_VEC3, "template", vertex_data);
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

int add_template_mesh(GlbBuilder& builder, const core::Mesh& mesh, const std::vector<std::uint8_t>& texture_png,
                      const std::string& name) {
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] =
      builder.add_floats(row_major_floats(mesh.V), TINYGLTF_TYPE_VEC3, "template", vertex_data, true);
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(mesh.F.size()));
  for (long f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) indices[f * 3 + k] = static_cast<std::uint32_t>(mesh.F(f, k));
  primitive.indices = builder.add_u32(indices, "template", index_data);
  if (mesh.has_colors()) primitive.attributes["COLOR_0"] = add_colors(builder, mesh.colors);
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
  builder.model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.name = name;
  scene.nodes.push_back(0);
  builder.model.scenes.push_back(scene);
  builder.model.defaultScene = 0;
  return node.mesh;
}

int add_morph_targets(GlbBuilder& builder, int mesh, const std::vector<float>& base,
                      const std::vector<Eigen::MatrixXd>& frames, const std::string& prefix,
                      std::vector<std::string>& names, TargetCorrections* corrections) {
  auto& targets = builder.model.meshes[mesh].primitives[0].targets;
  const int first = static_cast<int>(targets.size());
  std::vector<float> delta(base.size());
  for (std::size_t t = 0; t < frames.size(); ++t) {
    const std::vector<float> frame = row_major_floats(frames[t]);
    for (std::size_t i = 0; i < base.size(); ++i) {
      delta[i] = frame[i] - base[i];
      if (corrections && base[i] + delta[i] != frame[i]) {
        corrections->indices.push_back(static_cast<std::uint32_t>(t * base.size() + i));
        corrections->values.push_back(frame[i]);
      }
    }
    targets.push_back({{"POSITION", builder.add_floats(delta, TINYGLTF_TYPE_VEC3, "morph_targets", vertex_data, true)}});
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
  add_channel(animation, input, builder.add_floats(weights, TINYGLTF_TYPE_SCALAR, "animations"), "weights");
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
    add_channel(animation, input, builder.add_floats(translation, TINYGLTF_TYPE_VEC3, "animations"), "translation");
    add_channel(animation, input, builder.add_floats(rotation, TINYGLTF_TYPE_VEC4, "animations"), "rotation");
  }
  builder.model.animations.push_back(animation);
  return static_cast<int>(builder.model.animations.size()) - 1;
}

}  // namespace surfcap::asset::detail
