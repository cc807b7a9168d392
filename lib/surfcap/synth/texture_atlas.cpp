#include "surfcap/synth/texture_atlas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <string>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/synth/studio.hpp"

namespace surfcap::synth {
namespace {

Eigen::Vector3d sample(const render::Image& image, double x, double y) {
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, image.width - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, image.height - 1);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
  return (1 - fy) * ((1 - fx) * image.get(x0, y0) + fx * image.get(x1, y0)) +
         fy * ((1 - fx) * image.get(x0, y1) + fx * image.get(x1, y1));
}

struct Chart {
  int camera = 0;
  std::vector<int> faces;
  double x0 = 0, y0 = 0;  ///< camera pixel at the chart's first texel
  int width = 0, height = 0;
  int ox = 0, oy = 0;  ///< the chart's first texel in the atlas
};

}  // namespace

TexturedMesh bake_texture(const core::Mesh& mesh, const std::vector<render::Camera>& cameras,
                          const std::vector<render::Image>& images, const std::vector<int>& best_camera, double scale) {
  if (cameras.empty() || images.size() != cameras.size())
    throw core::internal_error("bake_texture: one image per camera is needed");
  const long n = mesh.vertex_count(), m = mesh.face_count();
  auto camera_of = [&](long f) { return std::max(0, best_camera[static_cast<std::size_t>(f)]); };
  // Charts: faces linked through an edge that the same camera sees best.
  DisjointSets parent(static_cast<std::size_t>(m));
  std::map<std::pair<int, int>, int> edge_face;
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(mesh.F(f, k), mesh.F(f, (k + 1) % 3));
      const auto found = edge_face.find(key);
      if (found == edge_face.end())
        edge_face.emplace(key, static_cast<int>(f));
      else if (camera_of(found->second) == camera_of(f))
        parent.unite(static_cast<int>(f), found->second);
    }
  std::vector<Chart> charts;
  std::vector<int> chart_of_root(static_cast<std::size_t>(m), -1), chart_of_face(static_cast<std::size_t>(m));
  for (long f = 0; f < m; ++f) {
    int& chart = chart_of_root[static_cast<std::size_t>(parent.find(static_cast<int>(f)))];
    if (chart < 0) {
      chart = static_cast<int>(charts.size());
      charts.push_back({camera_of(f), {}, 0, 0, 0, 0, 0, 0});
    }
    charts[static_cast<std::size_t>(chart)].faces.push_back(static_cast<int>(f));
    chart_of_face[static_cast<std::size_t>(f)] = chart;
  }
  // Each chart's extent in its camera, one pixel of margin.
  for (auto& chart : charts) {
    double x_min = 1e300, y_min = 1e300, x_max = -1e300, y_max = -1e300;
    for (const int f : chart.faces)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d p =
            cameras[static_cast<std::size_t>(chart.camera)].project(mesh.V.row(mesh.F(f, k)).transpose());
        x_min = std::min(x_min, p.x()), y_min = std::min(y_min, p.y());
        x_max = std::max(x_max, p.x()), y_max = std::max(y_max, p.y());
      }
    chart.x0 = std::floor(x_min) - 1;
    chart.y0 = std::floor(y_min) - 1;
    chart.width = static_cast<int>(std::ceil((std::ceil(x_max) + 1 - chart.x0) * scale)) + 1;
    chart.height = static_cast<int>(std::ceil((std::ceil(y_max) + 1 - chart.y0) * scale)) + 1;
    if (chart.width > 16384 || chart.height > 16384)
      throw core::internal_error("bake_texture: a chart spans " + std::to_string(chart.width) + " texels");
  }
  // Shelf packing, tallest first.
  std::vector<int> order(charts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return charts[static_cast<std::size_t>(a)].height > charts[static_cast<std::size_t>(b)].height;
  });
  double area = 0;
  int widest = 0;
  for (const auto& chart : charts) {
    area += static_cast<double>(chart.width + 1) * (chart.height + 1);
    widest = std::max(widest, chart.width + 1);
  }
  const int width = std::max(widest, static_cast<int>(std::ceil(std::sqrt(area * 1.2) / 4)) * 4);
  int x = 0, y = 0, shelf = 0;
  for (const int c : order) {
    Chart& chart = charts[static_cast<std::size_t>(c)];
    if (x + chart.width + 1 > width) x = 0, y += shelf, shelf = 0;
    chart.ox = x;
    chart.oy = y;
    x += chart.width + 1;
    shelf = std::max(shelf, chart.height + 1);
  }
  TexturedMesh result;
  result.charts = static_cast<long>(charts.size());
  result.atlas = render::Image(width, std::max(1, y + shelf), Eigen::Vector3d(0.5, 0.5, 0.5));
  for (const auto& chart : charts) {
    const render::Image& image = images[static_cast<std::size_t>(chart.camera)];
    for (int ty = 0; ty < chart.height; ++ty)
      for (int tx = 0; tx < chart.width; ++tx)
        result.atlas.set(chart.ox + tx, chart.oy + ty, sample(image, chart.x0 + tx / scale, chart.y0 + ty / scale));
  }
  // Corner UVs at texel centres, one per (chart, vertex).
  std::map<std::pair<int, int>, int> uv_index;
  std::vector<Eigen::Vector2i> texels;
  result.FT.resize(m, 3);
  for (long f = 0; f < m; ++f) {
    const Chart& chart = charts[static_cast<std::size_t>(chart_of_face[static_cast<std::size_t>(f)])];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      const auto key = std::make_pair(chart_of_face[static_cast<std::size_t>(f)], v);
      auto found = uv_index.find(key);
      if (found == uv_index.end()) {
        const Eigen::Vector2d p = cameras[static_cast<std::size_t>(chart.camera)].project(mesh.V.row(v).transpose());
        const int tx = std::clamp(static_cast<int>(std::lround((p.x() - chart.x0) * scale)), 0, chart.width - 1);
        const int ty = std::clamp(static_cast<int>(std::lround((p.y() - chart.y0) * scale)), 0, chart.height - 1);
        texels.emplace_back(chart.ox + tx, chart.oy + ty);
        found = uv_index.emplace(key, static_cast<int>(texels.size()) - 1).first;
      }
      result.FT(f, k) = found->second;
    }
  }
  // A vertex's colour is the texel at its first corner; every corner's texel is
  // set to it.
  std::vector<int> first_texel(static_cast<std::size_t>(n), -1);
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k)
      if (first_texel[static_cast<std::size_t>(mesh.F(f, k))] < 0)
        first_texel[static_cast<std::size_t>(mesh.F(f, k))] = result.FT(f, k);
  result.mesh.V = mesh.V;
  result.mesh.F = mesh.F;
  result.mesh.colors = Eigen::MatrixXd::Constant(n, 3, 0.5);
  for (long v = 0; v < n; ++v)
    if (first_texel[static_cast<std::size_t>(v)] >= 0) {
      const Eigen::Vector2i t = texels[static_cast<std::size_t>(first_texel[static_cast<std::size_t>(v)])];
      result.mesh.colors.row(v) = result.atlas.get(t.x(), t.y()).transpose();
    }
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2i t = texels[static_cast<std::size_t>(result.FT(f, k))];
      result.atlas.set(t.x(), t.y(), result.mesh.colors.row(mesh.F(f, k)).transpose());
    }
  for (long f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2i t = texels[static_cast<std::size_t>(result.FT(f, k))];
      const Eigen::Vector3d stored = result.atlas.get(t.x(), t.y());
      if ((stored - result.mesh.colors.row(mesh.F(f, k)).transpose()).cwiseAbs().maxCoeff() > 0.5 / 255)
        ++result.conflicting_corners;
    }
  result.uv.resize(static_cast<long>(texels.size()), 2);
  for (std::size_t i = 0; i < texels.size(); ++i)
    result.uv.row(static_cast<long>(i)) << (texels[i].x() + 0.5) / result.atlas.width,
        1.0 - (texels[i].y() + 0.5) / result.atlas.height;
  return result;
}

void write_textured_obj(const std::filesystem::path& obj_path, const TexturedMesh& textured) {
  const std::string stem = obj_path.stem().string();
  const auto folder = obj_path.parent_path();
  render::write_png(folder / (stem + ".png"), textured.atlas);
  core::write_file_atomically(folder / (stem + ".mtl"),
                              "newmtl surface\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd " + stem + ".png\n");
  std::string text = "# surfcap-synth textured reconstruction\nmtllib " + stem + ".mtl\n";
  char line[160];
  const auto& mesh = textured.mesh;
  for (long v = 0; v < mesh.vertex_count(); ++v) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
    text += line;
  }
  for (long t = 0; t < textured.uv.rows(); ++t) {
    std::snprintf(line, sizeof line, "vt %.9g %.9g\n", textured.uv(t, 0), textured.uv(t, 1));
    text += line;
  }
  text += "usemtl surface\n";
  for (long f = 0; f < mesh.face_count(); ++f) {
    std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n", mesh.F(f, 0) + 1, textured.FT(f, 0) + 1, mesh.F(f, 1) + 1,
                  textured.FT(f, 1) + 1, mesh.F(f, 2) + 1, textured.FT(f, 2) + 1);
    text += line;
  }
  core::write_file_atomically(obj_path, text);
}

}  // namespace surfcap::synth
