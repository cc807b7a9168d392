#include "surfcap/align/alignment_template.hpp"

#include <algorithm>
#include <chrono>
#include <numbers>

#include "surfcap/align/creases.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::align {

namespace {

TemplateSurface as_observed(core::Mesh mesh) {
  TemplateSurface surface;
  surface.observed_vertices = mesh.vertex_count();
  surface.observed_faces = mesh.face_count();
  surface.mesh = std::move(mesh);
  return surface;
}

}  // namespace

AlignmentTemplate::AlignmentTemplate(core::Mesh mesh, const PairwiseOptions& options, const DeformerOptions& deformer)
    : AlignmentTemplate(as_observed(std::move(mesh)), options, deformer) {}

AlignmentTemplate::AlignmentTemplate(TemplateSurface surface, const PairwiseOptions& options,
                                     const DeformerOptions& deformer, const std::vector<render::Camera>& cameras)
    : seconds_tetrahedralisation_(0),
      mesh_(std::move(surface.mesh)),
      deformer_([&] {
        const std::vector<char> unseen = unseen_vertices(mesh_.V, mesh_.F, cameras);
        unseen_vertices_ = std::count(unseen.begin(), unseen.end(), 1);
        const auto start = std::chrono::steady_clock::now();
        VolumeDeformer built(mesh_, deformer, unseen);
        seconds_tetrahedralisation_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return built;
      }()),
      patches_(patch_hierarchy(mesh_.V, mesh_.F, options.patches, options.levels)),
      mean_edge_(geometry::mean_edge_length(mesh_.V, mesh_.F)),
      height_(mesh_.V.col(1).maxCoeff() - mesh_.V.col(1).minCoeff()),
      observed_vertices_(surface.observed_vertices),
      observed_faces_(surface.observed_faces) {
  if (mesh_.has_colors()) smoothed_colors_ = smoothed_vertex_colors(mesh_.F, mesh_.colors, options.patch_color.smoothing);
  if (options.crease.weight)
    crease_vertices_ = straight_crease_vertices(
        mesh_.V, convex_crease_vertices(mesh_.V, mesh_.F, options.crease.angle_deg * std::numbers::pi / 180),
        options.crease.straight_radius_height * height_, options.crease.straightness.value_or(1.0));
  crease_vertices_.erase(std::remove_if(crease_vertices_.begin(), crease_vertices_.end(),
                                        [this](int v) { return !observed_vertex(v); }),
                         crease_vertices_.end());
}

double AlignmentTemplate::unobserved_fraction() const {
  const long n = mesh_.vertex_count();
  return n > 0 ? static_cast<double>(n - observed_vertices_) / static_cast<double>(n) : 0.0;
}

std::vector<char> unseen_vertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                  const std::vector<render::Camera>& cameras) {
  std::vector<char> unseen(static_cast<std::size_t>(V.rows()), 1);
  bool any = false;
  for (const render::Camera& camera : cameras)
    for (const int f : render::render_visibility(V, F, camera).face) {
      if (f < 0) continue;
      any = true;
      for (int k = 0; k < 3; ++k) unseen[static_cast<std::size_t>(F(f, k))] = 0;
    }
  if (!any) unseen.clear();
  return unseen;
}

Eigen::MatrixXd smoothed_vertex_colors(const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors, int rings) {
  Eigen::MatrixXd current = colors;
  if (rings <= 0 || colors.rows() == 0) return current;
  // Each face adds a vertex's two neighbours in it: a neighbour across an interior edge counts twice
  // (once per face sharing the edge), a uniform weighting on a closed mesh.
  Eigen::VectorXd count = Eigen::VectorXd::Ones(colors.rows());
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) count(F(f, k)) += 2;
  for (int ring = 0; ring < rings; ++ring) {
    Eigen::MatrixXd sum = current;
    for (long f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
        sum.row(a) += current.row(b) + current.row(c);
      }
    current = sum.array().colwise() / count.array();
  }
  return current;
}

}  // namespace surfcap::align
