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

struct Charts {
  std::vector<Chart> charts;
  std::vector<int> chart_of_face;
};

/// Faces linked through an edge that the same camera sees best form a chart.
Charts build_charts(const core::Mesh& mesh, const std::vector<int>& best_camera) {
  const long m = mesh.face_count();
  auto camera_of = [&](long f) { return std::max(0, best_camera[static_cast<std::size_t>(f)]); };
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
  Charts result;
  result.chart_of_face.resize(static_cast<std::size_t>(m));
  std::vector<int> chart_of_root(static_cast<std::size_t>(m), -1);
  for (long f = 0; f < m; ++f) {
    int& chart = chart_of_root[static_cast<std::size_t>(parent.find(static_cast<int>(f)))];
    if (chart < 0) {
      chart = static_cast<int>(result.charts.size());
      result.charts.push_back({camera_of(f), {}, 0, 0, 0, 0, 0, 0});
    }
    result.charts[static_cast<std::size_t>(chart)].faces.push_back(static_cast<int>(f));
    result.chart_of_face[static_cast<std::size_t>(f)] = chart;
  }
  return result;
}

/// Each chart's extent in its camera, one pixel of margin, in texels.
void measure_charts(const core::Mesh& mesh, const std::vector<render::Camera>& cameras, double scale,
                    std::vector<Chart>& charts) {
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
}

/// Shelf packing, tallest first; returns the atlas size.
Eigen::Vector2i pack_charts(std::vector<Chart>& charts) {
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
  return {width, std::max(1, y + shelf)};
}

/// The free texel of `chart` nearest to (tx, ty) (rings of growing radius, scanned in a fixed
/// order), or (tx, ty) itself when the chart has none left.
Eigen::Vector2i free_texel(const Chart& chart, int tx, int ty, const std::vector<int>& owner, int atlas_width) {
  auto is_free = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < chart.width && y < chart.height &&
           owner[static_cast<std::size_t>(chart.oy + y) * static_cast<std::size_t>(atlas_width) +
                 static_cast<std::size_t>(chart.ox + x)] < 0;
  };
  for (int r = 1; r < std::max(chart.width, chart.height); ++r)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx)
        if (std::max(std::abs(dx), std::abs(dy)) == r && is_free(tx + dx, ty + dy)) return {tx + dx, ty + dy};
  return {tx, ty};
}

/// Corner UVs at texel centres, one texel per (chart, vertex): the texel of the vertex's
/// projection, or the nearest free one when another vertex of the chart rounds to it.
std::vector<Eigen::Vector2i> assign_corner_texels(const core::Mesh& mesh, const std::vector<render::Camera>& cameras,
                                                  const Charts& charts, double scale, const Eigen::Vector2i& atlas_size,
                                                  Eigen::MatrixXi& FT) {
  std::map<std::pair<int, int>, int> uv_index;
  std::vector<Eigen::Vector2i> texels;
  std::vector<int> owner(static_cast<std::size_t>(atlas_size.x()) * static_cast<std::size_t>(atlas_size.y()), -1);
  FT.resize(mesh.face_count(), 3);
  for (long f = 0; f < mesh.face_count(); ++f) {
    const int c = charts.chart_of_face[static_cast<std::size_t>(f)];
    const Chart& chart = charts.charts[static_cast<std::size_t>(c)];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      auto found = uv_index.find({c, v});
      if (found == uv_index.end()) {
        const Eigen::Vector2d p = cameras[static_cast<std::size_t>(chart.camera)].project(mesh.V.row(v).transpose());
        Eigen::Vector2i t(std::clamp(static_cast<int>(std::lround((p.x() - chart.x0) * scale)), 0, chart.width - 1),
                          std::clamp(static_cast<int>(std::lround((p.y() - chart.y0) * scale)), 0, chart.height - 1));
        auto slot = [&](const Eigen::Vector2i& q) -> int& {
          return owner[static_cast<std::size_t>(chart.oy + q.y()) * static_cast<std::size_t>(atlas_size.x()) +
                       static_cast<std::size_t>(chart.ox + q.x())];
        };
        if (slot(t) >= 0) t = free_texel(chart, t.x(), t.y(), owner, atlas_size.x());
        slot(t) = v;
        texels.emplace_back(chart.ox + t.x(), chart.oy + t.y());
        found = uv_index.emplace(std::make_pair(c, v), static_cast<int>(texels.size()) - 1).first;
      }
      FT(f, k) = found->second;
    }
  }
  return texels;
}

}  // namespace

TexturedMesh bake_texture(const core::Mesh& mesh, const std::vector<render::Camera>& cameras,
                          const std::vector<render::Image>& images, const std::vector<int>& best_camera, double scale) {
  if (cameras.empty() || images.size() != cameras.size())
    throw core::internal_error("bake_texture: one image per camera is needed");
  const long n = mesh.vertex_count(), m = mesh.face_count();
  Charts charts = build_charts(mesh, best_camera);
  measure_charts(mesh, cameras, scale, charts.charts);
  const Eigen::Vector2i atlas_size = pack_charts(charts.charts);
  TexturedMesh result;
  result.charts = static_cast<long>(charts.charts.size());
  result.atlas = render::Image(atlas_size.x(), atlas_size.y(), Eigen::Vector3d(0.5, 0.5, 0.5));
  for (const auto& chart : charts.charts) {
    const render::Image& image = images[static_cast<std::size_t>(chart.camera)];
    for (int ty = 0; ty < chart.height; ++ty)
      for (int tx = 0; tx < chart.width; ++tx)
        result.atlas.set(chart.ox + tx, chart.oy + ty, sample(image, chart.x0 + tx / scale, chart.y0 + ty / scale));
  }
  const std::vector<Eigen::Vector2i> texels = assign_corner_texels(mesh, cameras, charts, scale, atlas_size, result.FT);
  // A vertex's colour is the texel at its first corner; every corner's texel is set to it.
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
