#include "surfcap/align/pairwise_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/silhouette_evidence.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/geometry/mesh_topology.hpp"
#include "surfcap/geometry/vertex_grid.hpp"

namespace surfcap::align {

namespace {

/// Each hard check relative to its limit: above 1 has failed (the largest names the failure).
std::array<double, 3> hard_scores(const PairwiseResult& r, const FailureOptions& options) {
  return {r.mean_residual / (options.failure_residual_mm / 1000), r.uncovered_fraction / options.max_uncovered,
          r.stacked_fraction / options.max_stacked};
}

}  // namespace

Eigen::VectorXd surface_distances(const Eigen::MatrixXd& surface, const geometry::SurfaceQuery& target) {
  Eigen::VectorXd distances(surface.rows());
  for (long i = 0; i < surface.rows(); ++i) distances(i) = target.closest_point(surface.row(i).transpose()).distance;
  return distances;
}

std::vector<long> far_from_vertices(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V, double gate) {
  std::vector<long> far;
  if (!(gate > 0)) {
    for (long i = 0; i < points.rows(); ++i) far.push_back(i);
    return far;
  }
  const geometry::VertexGrid grid(V, gate);
  const double near2 = gate * (1 - 1e-9) * gate * (1 - 1e-9);
  for (long i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d x = points.row(i).transpose();
    bool near = false;
    grid.around(x, [&](long v) { near = near || (V.row(v).transpose() - x).squaredNorm() <= near2; });
    if (!near) far.push_back(i);
  }
  return far;
}

double uncovered_fraction(const geometry::SurfaceQuery& target, const Eigen::MatrixXd& aligned,
                          const Eigen::MatrixXi& F, double gate, const std::vector<char>* counted,
                          const std::vector<render::Camera>* cameras) {
  const std::vector<long> far = far_from_vertices(target.vertices(), aligned, gate);
  long uncovered = 0;
  if (!far.empty()) {
    const geometry::SurfaceQuery query(aligned, F);
    const bool use_cameras = cameras != nullptr && !cameras->empty();
    std::optional<SilhouetteEvidence> evidence;  // rendered for the first vertex beyond the gate
    for (const long i : far) {
      if (counted && !(*counted)[static_cast<std::size_t>(i)]) continue;
      const Eigen::Vector3d x = target.vertices().row(i).transpose();
      const auto closest = query.closest_point_within(x, gate);
      if (closest && closest->distance <= gate) continue;
      if (use_cameras && !evidence) evidence.emplace(*cameras, aligned, F, gate);
      if (!use_cameras || evidence->outside(x)) ++uncovered;
    }
  }
  const long total = counted ? static_cast<long>(std::count(counted->begin(), counted->end(), 1))
                             : static_cast<long>(target.vertices().rows());
  return total > 0 ? static_cast<double>(uncovered) / static_cast<double>(total) : 0.0;
}

double stacked_fraction(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                        double distance, double rest_distance) {
  const long n = aligned.rows();
  if (n == 0 || distance <= 0) return 0.0;
  const std::vector<char> stacked = stacked_vertices(rest, aligned, F, distance, rest_distance);
  return static_cast<double>(std::count(stacked.begin(), stacked.end(), 1)) / static_cast<double>(n);
}

std::vector<char> stacked_vertices(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                                   double distance, double rest_distance) {
  const long n = aligned.rows();
  if (n == 0 || distance <= 0) return std::vector<char>(static_cast<std::size_t>(n), 0);
  const Eigen::MatrixXd normals = core::vertex_normals(aligned, F);
  const geometry::VertexGrid grid(aligned, distance);
  std::vector<char> stacked(static_cast<std::size_t>(n), 0);
  const double d2 = distance * distance, r2 = rest_distance * rest_distance;
  for (long v = 0; v < n; ++v)
    grid.around(aligned.row(v).transpose(), [&](long u) {
      if (u <= v || (aligned.row(u) - aligned.row(v)).squaredNorm() > d2) return;
      if ((rest.row(u) - rest.row(v)).squaredNorm() <= r2 || normals.row(u).dot(normals.row(v)) <= 0.5) return;
      stacked[static_cast<std::size_t>(u)] = stacked[static_cast<std::size_t>(v)] = 1;
    });
  return stacked;
}

MergedRegions merged_regions(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                             const geometry::SurfaceQuery& target, double mean_edge, double height) {
  const long n = aligned.rows();
  const double distance = MergedRegions::kDistanceEdges * mean_edge;
  const double rest_distance = MergedRegions::kRestDistanceHeight * height;
  MergedRegions result;
  result.merged.assign(static_cast<std::size_t>(n), 0);
  if (n == 0 || distance <= 0) return result;
  const Eigen::MatrixXd normals = core::vertex_normals(aligned, F);
  const geometry::VertexGrid grid(aligned, distance);
  const double d2 = distance * distance, r2 = rest_distance * rest_distance;
  for (long v = 0; v < n; ++v)
    grid.around(aligned.row(v).transpose(), [&](long u) {
      if (u <= v) return;
      const double gap2 = (aligned.row(u) - aligned.row(v)).squaredNorm();
      if (gap2 > d2 || normals.row(u).dot(normals.row(v)) >= -0.5 || (rest.row(u) - rest.row(v)).squaredNorm() <= r2)
        return;
      // Face to face: merged when the reconstruction has no surface between them.
      const Eigen::Vector3d halfway = 0.5 * (aligned.row(u) + aligned.row(v)).transpose();
      const double clearance = std::max(std::sqrt(gap2), mean_edge);
      const auto closest = target.closest_point_within(halfway, clearance);
      if (closest && closest->distance <= clearance) return;
      result.merged[static_cast<std::size_t>(u)] = result.merged[static_cast<std::size_t>(v)] = 1;
    });
  // Connected pieces over the faces; those under kMinimumRegion vertices are dropped.
  const std::vector<std::vector<int>> adjacency = geometry::vertex_adjacency(F, n);
  std::vector<char> visited(static_cast<std::size_t>(n), 0);
  long kept = 0;
  for (long s = 0; s < n; ++s) {
    if (!result.merged[static_cast<std::size_t>(s)] || visited[static_cast<std::size_t>(s)]) continue;
    std::vector<int> piece{static_cast<int>(s)};
    visited[static_cast<std::size_t>(s)] = 1;
    for (std::size_t i = 0; i < piece.size(); ++i)
      for (const int u : adjacency[static_cast<std::size_t>(piece[i])])
        if (result.merged[static_cast<std::size_t>(u)] && !visited[static_cast<std::size_t>(u)]) {
          visited[static_cast<std::size_t>(u)] = 1;
          piece.push_back(u);
        }
    if (static_cast<long>(piece.size()) >= MergedRegions::kMinimumRegion) {
      ++result.regions;
      kept += static_cast<long>(piece.size());
    } else {
      for (const int u : piece) result.merged[static_cast<std::size_t>(u)] = 0;
    }
  }
  result.fraction = static_cast<double>(kept) / static_cast<double>(n);
  return result;
}

Verdict verdict(const PairwiseResult& result, double parent_residual, const FailureOptions& options) {
  const auto scores = hard_scores(result, options);
  if (*std::max_element(scores.begin(), scores.end()) > 1) return Verdict::failed;
  const bool grown = options.residual_growth && parent_residual > 0 &&
                     result.mean_residual > *options.residual_growth * parent_residual;
  return grown ? Verdict::grown : Verdict::pass;
}

std::string failure_reason(const PairwiseResult& result, double parent_residual, const FailureOptions& options) {
  static const char* const reasons[] = {"mean residual above the failure threshold",
                                        "reconstruction not covered by the aligned template",
                                        "aligned template stacked onto itself"};
  if (verdict(result, parent_residual, options) == Verdict::grown) return "mean residual grown beyond its parent's";
  const auto scores = hard_scores(result, options);
  return reasons[std::max_element(scores.begin(), scores.end()) - scores.begin()];
}

}  // namespace surfcap::align
