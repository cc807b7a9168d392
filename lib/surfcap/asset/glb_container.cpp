#include "surfcap/asset/glb_container.hpp"

#include <cstring>
#include <limits>

#include "surfcap/core/error.hpp"

namespace surfcap::asset {
namespace {

constexpr std::uint32_t glb_magic = 0x46546C67;  // "glTF"
constexpr std::uint32_t json_chunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t bin_chunk = 0x004E4942;   // "BIN\0"

void put_u32(std::string& out, std::uint32_t value) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((value >> (8 * k)) & 0xFF));
}

std::uint32_t get_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int k = 0; k < 4; ++k) value |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
  return value;
}

std::size_t padded(std::size_t size) { return (size + 3) / 4 * 4; }

}  // namespace

std::string pack_glb(std::string_view json, std::span<const std::uint8_t> bin) {
  const std::size_t json_length = padded(json.size());
  const std::size_t bin_length = padded(bin.size());
  const std::size_t total = 12 + 8 + json_length + (bin.empty() ? 0 : 8 + bin_length);
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw core::internal_error("the character does not fit into a GLB file (" + std::to_string(total) +
                               " bytes, the format addresses at most 4 GiB)");
  std::string out;
  out.reserve(total);
  put_u32(out, glb_magic);
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(total));
  put_u32(out, static_cast<std::uint32_t>(json_length));
  put_u32(out, json_chunk);
  out.append(json);
  out.append(json_length - json.size(), ' ');
  if (!bin.empty()) {
    put_u32(out, static_cast<std::uint32_t>(bin_length));
    put_u32(out, bin_chunk);
    out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    out.append(bin_length - bin.size(), '\0');
  }
  return out;
}

GlbChunks unpack_glb(std::string_view bytes, const std::filesystem::path& source) {
  auto fail = [&](const std::string& what) { return core::bad_input(source, "not a valid GLB file: " + what); };
  if (bytes.size() < 20) throw fail("shorter than a GLB header (" + std::to_string(bytes.size()) + " bytes)");
  if (get_u32(bytes, 0) != glb_magic) throw fail("no \"glTF\" magic");
  if (get_u32(bytes, 4) != 2) throw fail("container version " + std::to_string(get_u32(bytes, 4)) + ", expected 2");
  const std::uint64_t length = get_u32(bytes, 8);
  if (length != bytes.size())
    throw fail("header declares " + std::to_string(length) + " bytes but the file has " + std::to_string(bytes.size()) +
               " (truncated?)");
  const std::uint64_t json_length = get_u32(bytes, 12);
  if (get_u32(bytes, 16) != json_chunk) throw fail("the first chunk is not JSON");
  if (json_length == 0 || json_length % 4 != 0 || 20 + json_length > length)
    throw fail("JSON chunk length " + std::to_string(json_length) + " is not a positive multiple of 4 within the file");
  GlbChunks chunks;
  chunks.json = bytes.substr(20, json_length);
  while (!chunks.json.empty() && (chunks.json.back() == ' ' || chunks.json.back() == '\0'))
    chunks.json.remove_suffix(1);
  std::uint64_t at = 20 + json_length;
  if (at == length) return chunks;
  if (at + 8 > length) throw fail("truncated BIN chunk header");
  const std::uint64_t bin_length = get_u32(bytes, at);
  if (get_u32(bytes, at + 4) != bin_chunk) throw fail("the second chunk is not BIN");
  if (bin_length % 4 != 0 || at + 8 + bin_length > length)
    throw fail("BIN chunk length " + std::to_string(bin_length) + " is not a multiple of 4 within the file");
  chunks.bin = bytes.substr(at + 8, bin_length);
  // Chunks of unknown types may follow (glTF 2.0 §4.4.3.1: clients ignore them); walk their headers.
  for (at += 8 + bin_length; at < length;) {
    if (at + 8 > length) throw fail("truncated chunk header at byte " + std::to_string(at));
    const std::uint64_t extra = get_u32(bytes, at);
    if (extra % 4 != 0 || at + 8 + extra > length) throw fail("chunk at byte " + std::to_string(at) + " overruns the file");
    at += 8 + extra;
  }
  return chunks;
}

}  // namespace surfcap::asset
