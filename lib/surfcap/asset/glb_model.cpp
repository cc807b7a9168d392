// The one translation unit holding tinygltf's implementation (no image codecs, no file system:
// images stay PNG bytes and a character never reads files beside it).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS
#include <fstream>  // tiny_gltf.h uses std::ofstream even without its file system callbacks
#include "surfcap/asset/glb_model.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "surfcap/asset/glb_container.hpp"

namespace surfcap::asset::detail {

int components_of(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

namespace {
std::size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}
/// "VEC3 of float" etc. for messages.
std::string element_name(int component_type, int type) {
  static const std::map<int, std::string> types = {{TINYGLTF_TYPE_SCALAR, "SCALAR"}, {TINYGLTF_TYPE_VEC2, "VEC2"},
                                                   {TINYGLTF_TYPE_VEC3, "VEC3"},     {TINYGLTF_TYPE_VEC4, "VEC4"},
                                                   {TINYGLTF_TYPE_MAT2, "MAT2"},     {TINYGLTF_TYPE_MAT3, "MAT3"},
                                                   {TINYGLTF_TYPE_MAT4, "MAT4"}};
  static const std::map<int, std::string> components = {
      {TINYGLTF_COMPONENT_TYPE_BYTE, "byte"}, {u8, "unsigned byte"}, {TINYGLTF_COMPONENT_TYPE_SHORT, "short"},
      {u16, "unsigned short"}, {u32, "unsigned int"}, {f32, "float"}};
  const auto t = types.find(type);
  const auto c = components.find(component_type);
  return (t == types.end() ? "type " + std::to_string(type) : t->second) + " of " +
         (c == components.end() ? "component type " + std::to_string(component_type) : c->second);
}

}  // namespace

GlbBuilder::GlbBuilder(const std::string& generator, bool compress) : compress_(compress) {
  model.asset.version = "2.0";
  model.asset.generator = generator;
  model.buffers.emplace_back();
}

int GlbBuilder::add_view(const void* bytes, std::size_t size, const std::string& kind, int target, ViewCodec codec,
                         int byte_stride) {
  bin_.resize((bin_.size() + 3) / 4 * 4, 0);  // every view 4-byte aligned (glTF 2.0 §3.6.2.4)
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = bin_.size();
  view.byteLength = size;
  view.byteStride = byte_stride;
  view.target = target;
  const auto* begin = static_cast<const unsigned char*>(bytes);
  const int index = static_cast<int>(model.bufferViews.size());
  if (compress_ && codec.stride > 0 && size >= 256) {
    // The decoded view holds whole elements: its length is rounded up to the stride.
    const std::size_t stride = codec.stride, count = (size + stride - 1) / stride;
    std::vector<unsigned char> data(count * stride, 0);
    std::memcpy(data.data(), begin, size);
    std::vector<unsigned char> encoded(meshopt_encodeVertexBufferBound(count, stride));
    encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), data.data(), count, stride));
    fallback_bytes_ = (fallback_bytes_ + 3) / 4 * 4;
    compressed_[index] = {fallback_bytes_, count * stride, bin_.size(), encoded.size(), codec.stride};
    fallback_bytes_ += count * stride;
    view.byteLength = count * stride;
    bin_.insert(bin_.end(), encoded.begin(), encoded.end());
    bytes_by_kind_[kind] += encoded.size();
  } else {
    bin_.insert(bin_.end(), begin, begin + size);
    bytes_by_kind_[kind] += size;
  }
  model.bufferViews.push_back(view);
  return index;
}

int GlbBuilder::add_accessor(const void* data, std::size_t count, int component_type, int type,
                             const std::string& kind, int target, bool normalized, ViewCodec codec) {
  if (count == 0) return -1;
  tinygltf::Accessor accessor;
  accessor.bufferView =
      add_view(data, count * components_of(type) * component_size(component_type), kind, target, codec);
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  accessor.normalized = normalized;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

namespace {
/// The bounds and 4-byte padded elements of a normalized integer VEC3 vertex attribute.
template <class Integer>
std::vector<Integer> padded_vec3(const std::vector<Integer>& xyz, tinygltf::Accessor& accessor) {
  const std::size_t count = xyz.size() / 3, lanes = 4;
  std::vector<Integer> padded(count * lanes, 0);  // vertex attribute elements are 4-byte aligned
  accessor.minValues.assign(3, std::numeric_limits<double>::infinity());
  accessor.maxValues.assign(3, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    padded[i / 3 * lanes + i % 3] = xyz[i];
    accessor.minValues[i % 3] = std::min<double>(accessor.minValues[i % 3], xyz[i]);
    accessor.maxValues[i % 3] = std::max<double>(accessor.maxValues[i % 3], xyz[i]);
  }
  return padded;
}
}  // namespace

template <class Integer>
int GlbBuilder::add_normalized(const std::vector<Integer>& xyz, const std::string& kind) {
  static_assert(sizeof(Integer) == 1 || sizeof(Integer) == 2);
  const std::size_t count = xyz.size() / 3;
  if (count == 0) return -1;
  tinygltf::Accessor accessor;
  const std::vector<Integer> padded = padded_vec3(xyz, accessor);
  const int stride = static_cast<int>(padded.size() / count * sizeof(Integer));
  accessor.bufferView = add_view(padded.data(), padded.size() * sizeof(Integer), kind, vertex_data, exact_codec(stride), stride);
  accessor.componentType = sizeof(Integer) == 1 ? TINYGLTF_COMPONENT_TYPE_BYTE : i16;
  accessor.type = TINYGLTF_TYPE_VEC3;
  accessor.count = count;
  accessor.normalized = true;
  quantised_ = true;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}
template int GlbBuilder::add_normalized(const std::vector<std::int8_t>&, const std::string&);
template int GlbBuilder::add_normalized(const std::vector<std::int16_t>&, const std::string&);

int GlbBuilder::add_floats(const std::vector<float>& values, int type, const std::string& kind, int target,
                           bool bounds, ViewCodec codec) {
  const int components = components_of(type);
  const int index = add_accessor(values.data(), values.size() / components, f32, type, kind, target, false, codec);
  if (index >= 0 && bounds) {
    auto& accessor = model.accessors[index];
    accessor.minValues.assign(components, std::numeric_limits<double>::infinity());
    accessor.maxValues.assign(components, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
      accessor.minValues[i % components] = std::min<double>(accessor.minValues[i % components], values[i]);
      accessor.maxValues[i % components] = std::max<double>(accessor.maxValues[i % components], values[i]);
    }
  }
  return index;
}

std::string GlbBuilder::finish(const core::Json& extensions) {
  // tinygltf writes the JSON of an empty buffer; the data is ours, byteLength is patched below.
  tinygltf::TinyGLTF writer;
  std::ostringstream stream;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true))
    throw core::internal_error("tinygltf could not serialise the glTF model");
  const std::string glb = stream.str();
  core::Json json = core::Json::parse(unpack_glb(glb, "<tinygltf output>").json);
  json["buffers"][0]["byteLength"] = bin_.size();
  if (!extensions.empty()) {
    for (const auto& [name, object] : extensions.items()) {
      json["extensions"][name] = object;
      json["extensionsUsed"].push_back(name);
    }
  }
  if (!compressed_.empty()) {
    // EXT_meshopt_compression: the compressed streams live in the BIN chunk (buffer 0); the views
    // point into buffer 1, which holds no data (no uri) and is what a decoder fills.
    json["buffers"].push_back({{"byteLength", fallback_bytes_},
                               {"extensions", {{meshopt_extension, {{"fallback", true}}}}}});
    for (const auto& [index, c] : compressed_) {
      core::Json& view = json["bufferViews"][index];
      view["buffer"] = 1;
      view["byteOffset"] = c.fallback_offset;
      view["byteLength"] = c.size;
      core::Json codec = {{"buffer", 0}, {"byteOffset", c.bin_offset}, {"byteLength", c.bin_size},
                          {"byteStride", c.stride}, {"count", c.size / c.stride}, {"mode", "ATTRIBUTES"}};
      view["extensions"][meshopt_extension] = codec;
    }
    json["extensionsUsed"].push_back(meshopt_extension);
    json["extensionsRequired"].push_back(meshopt_extension);
  }
  if (quantised_) {
    json["extensionsUsed"].push_back(quantization_extension);
    json["extensionsRequired"].push_back(quantization_extension);
  }
  return pack_glb(json.dump(), bin_);
}

GlbAccessors::GlbAccessors(const tinygltf::Model& model, std::string_view bin, std::filesystem::path source)
    : model_(model), bin_(bin), source_(std::move(source)) {}

const tinygltf::Accessor& GlbAccessors::accessor(int index, const std::string& what) const {
  if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
    throw core::bad_input(source_, what + ": accessor " + std::to_string(index) + " does not exist");
  return model_.accessors[index];
}

long GlbAccessors::count(int index, const std::string& what) const {
  return static_cast<long>(accessor(index, what).count);
}

std::string_view GlbAccessors::view_bytes(int index, const std::string& what) const {
  if (index < 0 || index >= static_cast<int>(model_.bufferViews.size()))
    throw core::bad_input(source_, what + ": bufferView " + std::to_string(index) + " does not exist");
  const auto& view = model_.bufferViews[index];
  if (view.buffer != 0 || !model_.buffers.at(0).uri.empty())
    throw core::bad_input(source_, what + ": data outside the GLB BIN chunk");
  const std::uint64_t end = static_cast<std::uint64_t>(view.byteOffset) + view.byteLength;
  if (end > bin_.size() || end < view.byteOffset)
    throw core::bad_input(source_, what + ": bufferView " + std::to_string(index) + " overruns the BIN chunk");
  return bin_.substr(view.byteOffset, view.byteLength);
}

GlbAccessors::Span GlbAccessors::locate(int index, int component_type, int type, long count, const std::string& what,
                                        bool normalized, std::size_t size) const {
  const auto& a = accessor(index, what);
  auto fail = [&](const std::string& problem) {
    return core::bad_input(source_, what + " (accessor " + std::to_string(index) + "): " + problem);
  };
  if (a.componentType != component_type || a.type != type)
    throw fail(element_name(a.componentType, a.type) + ", expected " + element_name(component_type, type));
  if (component_size(component_type) != size) throw core::internal_error("accessor read with a mismatched C++ type");
  if (a.normalized != normalized) throw fail(normalized ? "must be normalized" : "must not be normalized");
  if (a.sparse.isSparse) throw fail("sparse accessors are not supported here");
  if (count >= 0 && static_cast<long>(a.count) != count)
    throw fail(std::to_string(a.count) + " elements, expected " + std::to_string(count));
  if (a.bufferView < 0) throw fail("no bufferView");
  const std::string_view view = view_bytes(a.bufferView, what);
  const auto element = static_cast<std::uint64_t>(components_of(type)) * size;
  const int view_stride = model_.bufferViews[a.bufferView].byteStride;
  const std::uint64_t stride = view_stride > 0 ? static_cast<std::uint64_t>(view_stride) : element;
  if (stride < element || stride % size != 0) throw fail("interleaved data is not supported here");
  if (a.count > view.size()) throw fail("overruns its bufferView");
  const std::uint64_t bytes = a.count == 0 ? 0 : (static_cast<std::uint64_t>(a.count) - 1) * stride + element;
  if (a.byteOffset % size != 0 || a.byteOffset + bytes > view.size()) throw fail("overruns its bufferView");
  const std::uint64_t offset = static_cast<std::uint64_t>(view.data() - bin_.data()) + a.byteOffset;
  if (offset % size != 0) throw fail("misaligned data");
  return {static_cast<std::size_t>(offset), static_cast<std::size_t>(a.count * components_of(type)),
          static_cast<std::size_t>(a.count), static_cast<std::size_t>(stride)};
}

namespace {
bool keep_image_bytes(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                      void*) {
  return true;  // images are carried as PNG bytes, never decoded
}
}  // namespace

tinygltf::Model load_gltf(std::string_view glb_bytes, const std::filesystem::path& source) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_image_bytes, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const bool ok = loader.LoadBinaryFromMemory(&model, &error, &warning,
                                              reinterpret_cast<const unsigned char*>(glb_bytes.data()),
                                              static_cast<unsigned int>(glb_bytes.size()), "");
  if (!ok) throw core::bad_input(source, "not a valid glTF file: " + (error.empty() ? warning : error));
  if (model.buffers.empty()) throw core::bad_input(source, "no buffer");
  // A character is one self-contained file: an image or buffer naming a URI (a file beside it,
  // file:///etc/shadow, a web address) is refused, never followed.
  for (const auto& image : model.images)
    if (!image.uri.empty()) throw core::bad_input(source, "an image refers to the external URI '" + image.uri.substr(0, 200) + "'");
  for (const auto& buffer : model.buffers)
    if (!buffer.uri.empty()) throw core::bad_input(source, "a buffer refers to the external URI '" + buffer.uri.substr(0, 200) + "'");
  return model;
}

}  // namespace surfcap::asset::detail
