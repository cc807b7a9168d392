#include "test_support.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <unistd.h>

namespace surfcap::testing {

TemporaryDirectory::TemporaryDirectory(const std::string& name) {
  path_ = std::filesystem::path(SURFCAP_BINARY_DIR) / "test-tmp" / (name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TemporaryDirectory::~TemporaryDirectory() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

core::Mesh make_sphere(int rings, int segments, double radius) {
  core::Mesh mesh;
  const int ring_vertices = (rings - 1) * segments;
  mesh.V.resize(ring_vertices + 2, 3);
  mesh.V.row(0) << 0, radius, 0;
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      mesh.V.row(1 + (r - 1) * segments + s) << radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta),
          radius * std::sin(theta) * std::sin(phi);
    }
  }
  const int south = ring_vertices + 1;
  mesh.V.row(south) << 0, -radius, 0;
  std::vector<Eigen::Vector3i> faces;
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) faces.emplace_back(0, at(1, s + 1), at(1, s));
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      faces.emplace_back(at(r, s), at(r, s + 1), at(r + 1, s));
      faces.emplace_back(at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
    }
  for (int s = 0; s < segments; ++s) faces.emplace_back(south, at(rings - 1, s), at(rings - 1, s + 1));
  mesh.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<long>(f)) = faces[f].transpose();
  return mesh;
}

int count_hidden_files(const std::filesystem::path& directory) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory))
    if (entry.path().filename().string().front() == '.') ++count;
  return count;
}

double signed_volume(const core::Mesh& mesh) {
  double volume = 0;
  for (long f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

}  // namespace surfcap::testing
