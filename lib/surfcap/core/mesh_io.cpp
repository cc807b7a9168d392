#include "surfcap/core/mesh_io.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <optional>
#include <cctype>
#include <fstream>
#include <mutex>
#include <sstream>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/mesh_precheck.hpp"
#include "surfcap/core/textured_obj.hpp"

namespace surfcap::core {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using Color = OpenMesh::Vec3uc;
};
using OMMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh's reader and writer modules are process-wide singletons with per-read state.
std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}

void silence_openmesh() {
  static std::once_flag once;
  std::call_once(once, [] {
    omerr().disable();
    omout().disable();
    omlog().disable();
  });
}

/// Records the file's vertices and faces exactly as read (before OpenMesh drops or splits
/// anything), so that validation sees the file's real connectivity.
class RecordingImporter : public OpenMesh::IO::ImporterT<OMMesh> {
 public:
  using Base = OpenMesh::IO::ImporterT<OMMesh>;
  using Base::Base;

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return record(Base::add_vertex(p)); }
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override { return record(Base::add_vertex(p)); }
  OpenMesh::VertexHandle add_vertex() override { return record(Base::add_vertex()); }

  OpenMesh::FaceHandle add_face(const VHandles& indices) override {
    ++polygons;
    for (std::size_t k = 1; k + 1 < indices.size(); ++k)
      triangles.push_back({indices[0].idx(), indices[k].idx(), indices[k + 1].idx()});
    if (indices.size() < 3) ++short_polygons;
    return Base::add_face(indices);
  }

  long file_vertices = 0;
  long polygons = 0;
  long short_polygons = 0;
  std::vector<std::array<int, 3>> triangles;

 private:
  OpenMesh::VertexHandle record(OpenMesh::VertexHandle handle) {
    ++file_vertices;
    return handle;
  }
};

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void check_extension(const std::filesystem::path& path, const std::string& extension) {
  if (extension != ".obj" && extension != ".ply" && extension != ".off")
    throw bad_arguments("'" + path.string() + "': unsupported mesh format '" + extension +
                        "' (surfcap reads and writes .obj, .ply and .off)");
}

Mesh mesh_from_recording(const OMMesh& om, const RecordingImporter& importer, bool has_colors, bool has_uvs) {
  Mesh mesh;
  const long n = importer.file_vertices;
  mesh.V.resize(n, 3);
  for (long v = 0; v < n; ++v) {
    const auto& p = om.point(OpenMesh::VertexHandle(static_cast<int>(v)));
    mesh.V.row(v) << p[0], p[1], p[2];
  }
  mesh.F.resize(static_cast<long>(importer.triangles.size()), 3);
  for (std::size_t f = 0; f < importer.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(static_cast<long>(f), k) = importer.triangles[f][k];
  if (has_colors && om.has_vertex_colors()) {
    mesh.colors.resize(n, 3);
    for (long v = 0; v < n; ++v) {
      const auto& c = om.color(OpenMesh::VertexHandle(static_cast<int>(v)));
      mesh.colors.row(v) << c[0] / 255.0, c[1] / 255.0, c[2] / 255.0;
    }
  }
  if (has_uvs && om.has_vertex_texcoords2D()) {
    mesh.uvs.resize(n, 2);
    for (long v = 0; v < n; ++v) {
      const auto& t = om.texcoord2D(OpenMesh::VertexHandle(static_cast<int>(v)));
      mesh.uvs.row(v) << t[0], t[1];
    }
  }
  return mesh;
}

/// For ASCII files: the first "nan"/"inf" token and its line, which OpenMesh's stream parsing
/// turns into misleading follow-up errors. Empty if none.
std::string find_non_finite_token(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      std::string lower;
      for (const char c : word) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
      if (!lower.empty() && (lower[0] == '-' || lower[0] == '+')) lower.erase(0, 1);
      if (lower == "nan" || lower == "inf" || lower == "infinity" || lower.rfind("nan(", 0) == 0)
        return "non-finite coordinate '" + word + "' at line " + std::to_string(number);
    }
  }
  return {};
}

struct PlyProperty {
  bool list = false;
  int size = 0, count_size = 0;  // bytes of the value (list: of an item) and of a list's count
};

struct PlyElement {
  std::string header;  // the "element" line's name
  long count = 0;
  std::vector<PlyProperty> properties;
  std::vector<std::string> lines;  // its property lines
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::vector<std::string> preamble;  // "ply", format, comments before the first element
  bool rewrite = false;               // a list counts with more than one byte
};

int ply_type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "double" || type == "float64") return 8;
  return 4;
}

/// The header's elements and properties, the property lines of lists with wider counts already
/// rewritten to uchar counts.
PlyHeader parse_ply_header(const std::string& text) {
  PlyHeader header;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::vector<std::string> t;
    for (std::string word; words >> word;) t.push_back(word);
    if (t.empty()) continue;
    if (t[0] == "format") header.format = t.size() > 1 ? t[1] : "";
    if (t[0] == "element" && t.size() == 3) {
      header.elements.push_back({t[1], std::stol(t[2]), {}, {}});
    } else if (t[0] == "property" && !header.elements.empty()) {
      PlyProperty property;
      if (t.size() == 5 && t[1] == "list") {
        property = {true, ply_type_size(t[3]), ply_type_size(t[2])};
        if (property.count_size != 1) {
          header.rewrite = true;
          line = "property list uchar " + t[3] + " " + t[4];
        }
      } else if (t.size() >= 3) {
        property.size = ply_type_size(t[1]);
      }
      header.elements.back().properties.push_back(property);
      header.elements.back().lines.push_back(line);
    } else if (header.elements.empty()) {
      header.preamble.push_back(line);
    } else {
      header.elements.back().lines.push_back(line);  // a comment between properties
    }
  }
  return header;
}

/// One record of a PLY body: each property as raw bytes (binary) or tokens (ASCII), lists as
/// their items; and which list is the longest.
struct PlyRecord {
  std::vector<std::vector<std::string>> values;
  std::size_t longest = 0, list_index = 0;
};

/// Reads the records of a PLY body in order, ASCII or binary of either byte order.
class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& content, std::size_t body, const std::string& format)
      : content_(content), text_(content.substr(body)), position_(body), ascii_(format == "ascii"),
        swap_((format == "binary_big_endian") != (std::endian::native == std::endian::big)) {}

  bool ascii() const { return ascii_; }

  PlyRecord read(const PlyElement& element) {
    PlyRecord record;
    std::vector<std::string> tokens;
    if (ascii_) {
      // line_ persists: past the end, getline leaves it as it was.
      do std::getline(text_, line_);
      while (line_.find_first_not_of(" \t\r") == std::string::npos && text_);
      std::istringstream words(line_);
      for (std::string word; words >> word;) tokens.push_back(word);
    }
    std::size_t next = 0;
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      std::vector<std::string> items;
      std::uint64_t n = 1;
      if (property.list) {
        n = ascii_ ? std::stoull(tokens.at(next++)) : read_count(property.count_size);
        if (!ascii_) position_ += static_cast<std::size_t>(property.count_size);
        if (n >= record.longest) record.longest = n, record.list_index = p;
      }
      for (std::uint64_t k = 0; k < n; ++k) {
        if (ascii_) {
          items.push_back(tokens.at(next++));
        } else {
          items.push_back(content_.substr(position_, static_cast<std::size_t>(property.size)));
          position_ += static_cast<std::size_t>(property.size);
        }
      }
      record.values.push_back(std::move(items));
    }
    return record;
  }

 private:
  std::uint64_t read_count(int size) const {
    std::uint64_t value = 0;
    for (int k = 0; k < size; ++k) {
      const auto byte = static_cast<std::uint64_t>(static_cast<unsigned char>(content_[position_ + static_cast<std::size_t>(k)]));
      value |= byte << (8 * (swap_ ? size - 1 - k : k));
    }
    return value;
  }

  const std::string& content_;
  std::istringstream text_;
  std::string line_;
  std::size_t position_;
  bool ascii_, swap_;
};

/// Appends `record` with uchar list counts to `out`: the record itself, or a fan of triangles over
/// its longest list when that list has more than 255 items. Returns the records written.
long write_byte_count_record(const PlyElement& element, const PlyRecord& record, bool ascii, std::string& out) {
  const bool fan = record.longest > 255;
  const std::size_t pieces = fan ? record.longest - 2 : 1;
  for (std::size_t piece = 0; piece < pieces; ++piece) {
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      std::vector<std::string> items = record.values[p];
      if (fan && p == record.list_index)
        items = {record.values[p][0], record.values[p][piece + 1], record.values[p][piece + 2]};
      if (element.properties[p].list) {
        if (ascii) out += std::to_string(items.size()) + " ";
        else out.push_back(static_cast<char>(items.size()));
      }
      for (const auto& item : items) out += ascii ? item + " " : item;
    }
    if (ascii) out += "\n";
  }
  return static_cast<long>(pieces);
}

/// OpenMesh reads PLY face lists only with a uchar count ("Unsupported Index type" otherwise), so a
/// legal PLY whose lists count with ushort, uint... is rewritten in memory with uchar counts; a
/// polygon of more than 255 vertices becomes a fan of triangles from its first vertex, as the
/// importer triangulates it anyway. Returns the rewritten file and its face count; nothing when
/// OpenMesh reads the file as it is. The file has passed precheck_mesh_file.
std::optional<std::pair<std::string, long>> ply_with_byte_counts(const std::string& content) {
  const std::size_t end = content.find("end_header");
  const std::size_t body = content.find('\n', end) + 1;
  const PlyHeader header = parse_ply_header(content.substr(0, end));
  if (!header.rewrite) return std::nullopt;
  PlyBodyReader reader(content, body, header.format);
  std::string out_body;
  long faces = -1;
  std::vector<long> counts;
  for (const PlyElement& element : header.elements) {
    long written = 0;
    for (long record = 0; record < element.count; ++record)
      written += write_byte_count_record(element, reader.read(element), reader.ascii(), out_body);
    counts.push_back(written);
    if (element.header == "face") faces = written;
  }
  std::string result;
  for (const auto& l : header.preamble) result += l + "\n";
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    result += "element " + header.elements[e].header + " " + std::to_string(counts[e]) + "\n";
    for (const auto& l : header.elements[e].lines) result += l + "\n";
  }
  return std::make_pair(result + "end_header\n" + out_body, faces);
}

Mesh read_and_validate(const std::filesystem::path& path, const std::string& extension,
                       const MeshRequirements& requirements, std::optional<long> frame) {
  check_extension(path, extension);
  check_regular_file(path, frame);  // before any open: a FIFO would block it
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw io_error(path, "cannot open for reading");
  }
  const MeshFileCounts declared = precheck_mesh_file(path, extension, frame);
  if (extension == ".obj") {
    const std::string text = read_file(path);
    if (obj_uses_materials(text)) {
      Mesh mesh = read_textured_obj(path, text, frame);
      validate_mesh(mesh, requirements, path, frame);
      return mesh;
    }
  }

  OMMesh om;
  om.request_vertex_colors();
  om.request_vertex_texcoords2D();
  RecordingImporter importer(om);
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexColor | OpenMesh::IO::Options::VertexTexCoord;
  bool ok = false;
  long declared_faces = declared.faces;
  {
    const auto rewritten = extension == ".ply" ? ply_with_byte_counts(read_file(path)) : std::nullopt;
    std::lock_guard lock(openmesh_mutex());
    silence_openmesh();
    if (rewritten) {
      std::istringstream stream(rewritten->first);
      declared_faces = rewritten->second;
      ok = OpenMesh::IO::IOManager().read(stream, extension, importer, options);
    } else {
      ok = OpenMesh::IO::IOManager().read(path.string(), importer, options);
    }
  }
  if (!ok) throw bad_input(path, "could not be parsed as " + extension.substr(1) + " (corrupt or truncated)", frame);
  if (declared.vertices >= 0 && importer.file_vertices != declared.vertices)
    throw bad_input(path, "truncated or corrupt: the header declares " + std::to_string(declared.vertices) +
                              " vertices, " + std::to_string(importer.file_vertices) + " were read", frame);
  if (declared_faces >= 0 && importer.polygons != declared_faces)
    throw bad_input(path, "truncated or corrupt: the header declares " + std::to_string(declared_faces) +
                              " faces, " + std::to_string(importer.polygons) + " were read", frame);
  if (importer.short_polygons > 0)
    throw bad_input(path, std::to_string(importer.short_polygons) + " faces have fewer than 3 vertices", frame);

  Mesh mesh = mesh_from_recording(om, importer, options.check(OpenMesh::IO::Options::VertexColor),
                                  options.check(OpenMesh::IO::Options::VertexTexCoord));
  if (mesh.V.size() > 0 && mesh.V.cwiseAbs().maxCoeff() > kMaxCoordinate)
    throw bad_input(path, "vertex coordinates beyond the plausible magnitude (|x| ≤ " + std::to_string(long(kMaxCoordinate)) +
                              " m)", frame);
  validate_mesh(mesh, requirements, path, frame);
  return mesh;
}

}  // namespace

Mesh read_mesh(const std::filesystem::path& path, const MeshRequirements& requirements, std::optional<long> frame) {
  try {
    return read_and_validate(path, lowercase_extension(path), requirements, frame);
  } catch (const Error& error) {
    if (error.code() != ExitCode::bad_input || !std::filesystem::is_regular_file(path)) throw;
    if (const std::string token = find_non_finite_token(path); !token.empty())
      throw bad_input(path, "NaN/Inf vertex coordinates: " + token, frame);
    throw;
  }
}

void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& write_options) {
  const std::string extension = lowercase_extension(path);
  check_extension(path, extension);
  OMMesh om;
  // OBJ has no standard per-vertex colour (OpenMesh's OBJ writer refuses the option).
  const bool colors = write_options.write_colors && mesh.has_colors() && extension != ".obj";
  const bool uvs = write_options.write_uvs && mesh.has_uvs();
  if (colors) om.request_vertex_colors();
  if (uvs) om.request_vertex_texcoords2D();
  std::vector<OMMesh::VertexHandle> handles(static_cast<std::size_t>(mesh.V.rows()));
  for (long v = 0; v < mesh.V.rows(); ++v) {
    auto handle = om.add_vertex(OMMesh::Point(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2)));
    handles[static_cast<std::size_t>(v)] = handle;
    if (colors) {
      auto channel = [&](int k) {
        return static_cast<unsigned char>(std::clamp(std::lround(mesh.colors(v, k) * 255.0), 0L, 255L));
      };
      om.set_color(handle, OMMesh::Color(channel(0), channel(1), channel(2)));
    }
    if (uvs) om.set_texcoord2D(handle, OMMesh::TexCoord2D(static_cast<float>(mesh.uvs(v, 0)),
                                                          static_cast<float>(mesh.uvs(v, 1))));
  }
  for (long f = 0; f < mesh.F.rows(); ++f) {
    const auto face = om.add_face(handles.at(static_cast<std::size_t>(mesh.F(f, 0))),
                                  handles.at(static_cast<std::size_t>(mesh.F(f, 1))),
                                  handles.at(static_cast<std::size_t>(mesh.F(f, 2))));
    if (!face.is_valid())
      throw internal_error("cannot write '" + path.string() + "': face " + std::to_string(f) +
                           " makes the mesh non-manifold");
  }
  OpenMesh::IO::Options options;
  if (colors) options += OpenMesh::IO::Options::VertexColor;
  if (uvs) options += OpenMesh::IO::Options::VertexTexCoord;
  if (write_options.binary && extension == ".ply") options += OpenMesh::IO::Options::Binary;
  if (extension == ".ply") options += OpenMesh::IO::Options::LSB;
  std::ostringstream buffer;
  bool ok = false;
  {
    std::lock_guard lock(openmesh_mutex());
    silence_openmesh();
    OpenMesh::IO::ExporterT<OMMesh> exporter(om);
    ok = OpenMesh::IO::IOManager().write(buffer, extension, exporter, options, std::streamsize(9));
  }
  if (!ok) throw internal_error("OpenMesh failed to write '" + path.string() + "'");
  write_file_atomically(path, buffer.str());
}

}  // namespace surfcap::core
