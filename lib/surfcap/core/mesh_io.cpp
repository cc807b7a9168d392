#include "surfcap/core/mesh_io.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <mutex>
#include <sstream>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/mesh_precheck.hpp"

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

Mesh read_and_validate(const std::filesystem::path& path, const std::string& extension,
                       const MeshRequirements& requirements, std::optional<long> frame) {
  check_extension(path, extension);
  check_regular_file(path, frame);  // before any open: a FIFO would block it
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw io_error(path, "cannot open for reading");
  }
  const MeshFileCounts declared = precheck_mesh_file(path, extension, frame);

  OMMesh om;
  om.request_vertex_colors();
  om.request_vertex_texcoords2D();
  RecordingImporter importer(om);
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexColor | OpenMesh::IO::Options::VertexTexCoord;
  bool ok = false;
  {
    std::lock_guard lock(openmesh_mutex());
    silence_openmesh();
    ok = OpenMesh::IO::IOManager().read(path.string(), importer, options);
  }
  if (!ok) throw bad_input(path, "could not be parsed as " + extension.substr(1) + " (corrupt or truncated)", frame);
  if (declared.vertices >= 0 && importer.file_vertices != declared.vertices)
    throw bad_input(path, "truncated or corrupt: the header declares " + std::to_string(declared.vertices) +
                              " vertices, " + std::to_string(importer.file_vertices) + " were read", frame);
  if (declared.faces >= 0 && importer.polygons != declared.faces)
    throw bad_input(path, "truncated or corrupt: the header declares " + std::to_string(declared.faces) +
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
    if (error.code() != ExitCode::bad_input) throw;
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
