#include "surfcap/asset/glb_meshopt.hpp"

#include <meshoptimizer.h>

#include <cstdint>
#include <vector>

#include "surfcap/asset/glb_container.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::asset::detail {
namespace {

constexpr const char* extension = "EXT_meshopt_compression";
// The vertex codec spends at least 2 bits per 16 byte deltas and a header per block, so no valid
// stream expands more than ~64×; a larger claim is refused before any allocation.
constexpr std::uint64_t max_expansion = 256;

std::uint64_t unsigned_field(const core::Json& object, const char* key, const std::filesystem::path& source,
                             const std::string& what) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned())
    throw core::bad_input(source, what + ": " + key + " must be a non-negative integer");
  return it->get<std::uint64_t>();
}

void remove_name(core::Json& json, const char* list) {
  if (!json.contains(list) || !json[list].is_array()) return;
  core::Json kept = core::Json::array();
  for (const auto& name : json[list])
    if (name != extension) kept.push_back(name);
  if (kept.empty()) json.erase(list);
  else json[list] = kept;
}

/// Decodes one view's stream into `out` (appended, 4-byte aligned); returns its offset there.
std::size_t decode_view(const core::Json& codec, std::string_view bin, std::uint64_t view_length,
                        std::vector<std::uint8_t>& out, const std::filesystem::path& source, const std::string& what) {
  if (unsigned_field(codec, "buffer", source, what) != 0) throw core::bad_input(source, what + ": the stream must be in the BIN chunk");
  const std::uint64_t offset = unsigned_field(codec, "byteOffset", source, what);
  const std::uint64_t length = unsigned_field(codec, "byteLength", source, what);
  const std::uint64_t stride = unsigned_field(codec, "byteStride", source, what);
  const std::uint64_t count = unsigned_field(codec, "count", source, what);
  const std::string mode = codec.value("mode", std::string());
  const std::string filter = codec.value("filter", std::string("NONE"));
  if (mode != "ATTRIBUTES") throw core::bad_input(source, what + ": mode '" + mode + "' is not supported (ATTRIBUTES only)");
  if (stride == 0 || stride % 4 != 0 || stride > 256) throw core::bad_input(source, what + ": byteStride must be 4..256, a multiple of 4");
  if (offset > bin.size() || length > bin.size() - offset) throw core::bad_input(source, what + ": the stream overruns the BIN chunk");
  if (count > view_length / stride || count * stride != view_length)
    throw core::bad_input(source, what + ": count × byteStride differs from the bufferView's byteLength");
  if (view_length > max_expansion * length + 4096) throw core::bad_input(source, what + ": implausible compression ratio");
  out.resize((out.size() + 3) / 4 * 4, 0);
  const std::size_t at = out.size();
  out.resize(at + view_length);
  if (meshopt_decodeVertexBuffer(out.data() + at, count, stride, reinterpret_cast<const unsigned char*>(bin.data() + offset),
                                 length) != 0)
    throw core::bad_input(source, what + ": the compressed stream does not decode");
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data() + at, count, stride);
  else if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) meshopt_decodeFilterOct(out.data() + at, count, stride);
  else if (filter == "QUATERNION" && stride == 8) meshopt_decodeFilterQuat(out.data() + at, count, stride);
  else if (filter != "NONE") throw core::bad_input(source, what + ": filter '" + filter + "' with byteStride " + std::to_string(stride) + " is not supported");
  return at;
}

}  // namespace

std::string decode_meshopt_glb(std::string_view glb, const std::filesystem::path& source) {
  const GlbChunks chunks = unpack_glb(glb, source);
  core::Json json;
  try {
    json = core::Json::parse(chunks.json);
  } catch (const nlohmann::json::exception& e) {
    throw core::bad_input(source, std::string("malformed glTF JSON: ") + e.what());
  }
  if (!json.is_object() || !json.contains("bufferViews") || !json["bufferViews"].is_array()) return {};
  std::vector<std::uint8_t> bin(chunks.bin.begin(), chunks.bin.end());
  int fallback = -1;
  bool any = false;
  for (std::size_t v = 0; v < json["bufferViews"].size(); ++v) {
    core::Json& view = json["bufferViews"][v];
    if (!view.is_object() || !view.contains("extensions") || !view["extensions"].is_object() ||
        !view["extensions"].contains(extension))
      continue;
    const std::string what = "bufferView " + std::to_string(v) + " (" + extension + ")";
    const core::Json& codec = view["extensions"][extension];
    if (!codec.is_object()) throw core::bad_input(source, what + ": not an object");
    const std::uint64_t buffer = unsigned_field(view, "buffer", source, what);
    if (fallback >= 0 && buffer != static_cast<std::uint64_t>(fallback))
      throw core::bad_input(source, what + ": compressed views must share one fallback buffer");
    if (buffer == 0 || buffer > 1'000'000) throw core::bad_input(source, what + ": the fallback buffer must not be the BIN chunk");
    fallback = static_cast<int>(buffer);
    view["byteOffset"] = decode_view(codec, chunks.bin, unsigned_field(view, "byteLength", source, what), bin, source, what);
    view["buffer"] = 0;
    view["extensions"].erase(extension);
    if (view["extensions"].empty()) view.erase("extensions");
    any = true;
  }
  if (!any) return {};
  // Only the decoded views may use the fallback buffer, and it must be the last one (no renumbering).
  core::Json& buffers = json["buffers"];
  if (!buffers.is_array() || static_cast<int>(buffers.size()) != fallback + 1)
    throw core::bad_input(source, std::string(extension) + ": the fallback buffer must be the last buffer");
  for (const auto& view : json["bufferViews"])
    if (view.is_object() && view.value("buffer", -1) == fallback)
      throw core::bad_input(source, std::string(extension) + ": an uncompressed view refers to the fallback buffer");
  buffers.erase(buffers.end() - 1);
  if (buffers.empty() || !buffers[0].is_object()) throw core::bad_input(source, "no GLB buffer");
  bin.resize((bin.size() + 3) / 4 * 4, 0);
  buffers[0]["byteLength"] = bin.size();
  remove_name(json, "extensionsUsed");
  remove_name(json, "extensionsRequired");
  return pack_glb(json.dump(), bin);
}

}  // namespace surfcap::asset::detail
