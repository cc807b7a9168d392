#pragma once
// Internal to lib/surfcap/asset/glb_*.cpp (tinygltf is a heavy header: never include this from
// another module). Building a glTF model whose data lives in one buffer, and reading accessors
// of a loaded one with every bound and shape checked.
#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::asset::detail {

/// glTF 2.0 constants (§5.1.2 accessor.componentType, §5.11.4 bufferView.target).
enum ComponentType : int { u8 = 5121, u16 = 5123, u32 = 5125, f32 = 5126 };
enum ViewTarget : int { no_target = 0, vertex_data = 34962, index_data = 34963 };

enum : int { i16 = 5122 };

inline constexpr const char* meshopt_extension = "EXT_meshopt_compression";
inline constexpr const char* quantization_extension = "KHR_mesh_quantization";

/// How a bufferView travels in the compressed form (EXT_meshopt_compression, mode ATTRIBUTES,
/// no filter): its bytes as elements of `stride` bytes (a multiple of 4; 0: stored as is),
/// losslessly.
struct ViewCodec {
  int stride = 0;
};
/// Lossless compression of elements of `bytes` bytes (a multiple of 4).
inline ViewCodec exact_codec(int bytes) { return {bytes}; }

/// The model under construction: one buffer (the GLB BIN chunk), one bufferView per accessor,
/// 4-byte aligned; bytes are tallied per content kind for the export report. With `compress`,
/// views given a codec are stored meshopt-encoded in the BIN chunk and decode into a second,
/// data-less fallback buffer (EXT_meshopt_compression).
class GlbBuilder {
 public:
  explicit GlbBuilder(const std::string& generator, bool compress = false);

  tinygltf::Model model;

  bool compressed() const { return compress_; }
  /// A bufferView over a copy of `bytes`; returns its index. `byte_stride` > 0 sets
  /// bufferView.byteStride (vertex attributes whose elements are not 4-byte multiples).
  int add_view(const void* bytes, std::size_t size, const std::string& kind, int target = no_target,
               ViewCodec codec = {}, int byte_stride = 0);
  /// An accessor over `count` elements of `type` (TINYGLTF_TYPE_*) at `data`; -1 (nothing
  /// added) when count is 0, since glTF accessors hold at least one element.
  int add_accessor(const void* data, std::size_t count, int component_type, int type, const std::string& kind,
                   int target = no_target, bool normalized = false, ViewCodec codec = {});
  /// Float accessor with per-component min/max (required for POSITION and animation inputs).
  int add_floats(const std::vector<float>& values, int type, const std::string& kind, int target = no_target,
                 bool bounds = false, ViewCodec codec = {});
  int add_u32(const std::vector<std::uint32_t>& values, const std::string& kind, int target = no_target,
              ViewCodec codec = {}) {
    return add_accessor(values.data(), values.size(), u32, TINYGLTF_TYPE_SCALAR, kind, target, false, codec);
  }
  /// VEC3 of normalized SHORT or BYTE (KHR_mesh_quantization: int16_t / int8_t) in a view of
  /// byteStride 8 / 4, with min/max (integer domain, as glTF requires): morph-target deltas
  /// within [−1, 1].
  template <class Integer>
  int add_normalized(const std::vector<Integer>& xyz, const std::string& kind);

  /// The GLB bytes: tinygltf serialises the standard glTF JSON, `extensions` (name → object,
  /// exact nlohmann JSON: tinygltf::Value drops nulls and empty arrays) is spliced in.
  std::string finish(const core::Json& extensions);

  const std::map<std::string, std::size_t>& bytes_by_kind() const { return bytes_by_kind_; }

 private:
  struct Compressed {
    std::size_t fallback_offset, size, bin_offset, bin_size;
    int stride;
  };
  bool compress_ = false;
  bool quantised_ = false;
  std::vector<unsigned char> bin_;
  std::size_t fallback_bytes_ = 0;
  std::map<int, Compressed> compressed_;  ///< by bufferView
  std::map<std::string, std::size_t> bytes_by_kind_;
};

/// Components per element of a TINYGLTF_TYPE_* (1 for SCALAR ... 16 for MAT4).
int components_of(int type);

/// Checked access to the accessors of a loaded model; every failure is bad_input naming `source`.
class GlbAccessors {
 public:
  GlbAccessors(const tinygltf::Model& model, std::string_view bin, std::filesystem::path source);

  /// Elements of accessor `index` (count < 0: any), after checking it is dense (no sparse),
  /// of the given component type and element type, unnormalised unless `normalized`, packed
  /// (or strided by its bufferView's byteStride) and within its bufferView and the BIN chunk.
  template <class T>
  std::vector<T> read(int index, int component_type, int type, long count, const std::string& what,
                      bool normalized = false) const {
    const Span span = locate(index, component_type, type, count, what, normalized, sizeof(T));
    std::vector<T> values(span.components);
    const std::size_t element = span.components == 0 ? 0 : span.components / span.elements * sizeof(T);
    if (span.stride == element && span.components > 0)
      std::memcpy(values.data(), bin_.data() + span.offset, span.components * sizeof(T));
    else
      for (std::size_t e = 0; e < span.elements; ++e)
        std::memcpy(reinterpret_cast<char*>(values.data()) + e * element, bin_.data() + span.offset + e * span.stride, element);
    if constexpr (std::is_floating_point_v<T>)
      for (const T value : values)
        if (!std::isfinite(value))
          throw core::bad_input(source_, what + " (accessor " + std::to_string(index) + "): NaN or infinite value");
    return values;
  }
  /// Element count of accessor `index` (bad_input if there is none).
  long count(int index, const std::string& what) const;
  const tinygltf::Accessor& accessor(int index, const std::string& what) const;
  const std::filesystem::path& source() const { return source_; }
  /// Raw bytes of bufferView `index` (bounds checked).
  std::string_view view_bytes(int index, const std::string& what) const;

 private:
  struct Span {
    std::size_t offset = 0;
    std::size_t components = 0;
    std::size_t elements = 0;
    std::size_t stride = 0;  ///< bytes from one element to the next
  };
  Span locate(int index, int component_type, int type, long count, const std::string& what, bool normalized,
              std::size_t component_size) const;

  const tinygltf::Model& model_;
  std::string_view bin_;
  std::filesystem::path source_;
};

/// Loads the glTF structures of a GLB file already checked by unpack_glb. External URIs are
/// refused (a character is one self-contained file) and images are not decoded.
tinygltf::Model load_gltf(std::string_view glb_bytes, const std::filesystem::path& source);

}  // namespace surfcap::asset::detail
