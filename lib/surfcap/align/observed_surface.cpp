#include "surfcap/align/observed_surface.hpp"

#include <algorithm>
#include <functional>
#include <numeric>
#include <queue>
#include <utility>

#include "surfcap/core/surface_topology.hpp"
#include "surfcap/geometry/mean_edge_length.hpp"

namespace surfcap::align {

Eigen::VectorXd piece_shares(long n, const Eigen::MatrixXi& F, long& pieces_below, double share) {
  std::vector<long> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0L);
  const auto find = [&](long i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 1; k < 3; ++k) {
      const long a = find(F(f, 0)), b = find(F(f, k));
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  std::vector<long> faces(static_cast<std::size_t>(n), 0);
  for (long f = 0; f < F.rows(); ++f) ++faces[static_cast<std::size_t>(find(F(f, 0)))];
  pieces_below = 0;
  for (long v = 0; v < n; ++v)
    if (find(v) == v && faces[static_cast<std::size_t>(v)] > 0 &&
        static_cast<double>(faces[static_cast<std::size_t>(v)]) < share * static_cast<double>(F.rows()))
      ++pieces_below;
  Eigen::VectorXd shares(n);
  for (long v = 0; v < n; ++v)
    shares(v) = static_cast<double>(faces[static_cast<std::size_t>(find(v))]) / static_cast<double>(std::max<long>(1, F.rows()));
  return shares;
}

ObservedSurface::ObservedSurface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) : F_(F) {
  core::Mesh mesh;
  mesh.V = V;
  mesh.F = F;
  const std::vector<core::BoundaryLoop> loops = core::boundary_loops(mesh);
  holes_ = static_cast<long>(loops.size());
  for (const auto& loop : loops) largest_hole_perimeter_ = std::max(largest_hole_perimeter_, loop.perimeter);
  const long n = V.rows();
  const Eigen::VectorXd shares = piece_shares(n, F, small_pieces_, kSmallPieceShare);
  if (loops.empty() && small_pieces_ == 0) return;
  band_ = kBoundaryBandEdges * geometry::mean_edge_length(V, F);
  boundary_distance_ = Eigen::VectorXd::Constant(n, band_);
  for (long v = 0; v < n; ++v)
    if (shares(v) < kSmallPieceShare) boundary_distance_(v) = 0;

  // Distance to the nearest boundary vertex along the edges (Dijkstra from every rim vertex),
  // explored only up to the band.
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(n));
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) neighbours[static_cast<std::size_t>(F(f, k))].push_back(F(f, (k + 1) % 3));
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (const auto& loop : loops)
    for (const int v : loop.vertices) {
      boundary_distance_(v) = 0;
      queue.emplace(0.0, v);
    }
  while (!queue.empty()) {
    const auto [distance, v] = queue.top();
    queue.pop();
    if (distance > boundary_distance_(v)) continue;
    for (const int w : neighbours[static_cast<std::size_t>(v)]) {
      const double through = distance + (V.row(v) - V.row(w)).norm();
      if (through < boundary_distance_(w)) {
        boundary_distance_(w) = through;
        queue.emplace(through, w);
      }
    }
  }
}

bool ObservedSurface::observed(const geometry::SurfacePoint& point) const {
  if (!partial()) return true;
  if (point.face < 0) return false;
  double distance = 0;
  for (int k = 0; k < 3; ++k) distance += point.barycentric[k] * boundary_distance_(F_(point.face, k));
  return distance >= band_ * (1 - 1e-12);
}

}  // namespace surfcap::align
