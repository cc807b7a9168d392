#include "surfcap/core/surface_topology.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>

namespace surfcap::core {
namespace {

std::uint64_t edge_key(int a, int b) {
  return (std::uint64_t{static_cast<std::uint32_t>(a)} << 32) | static_cast<std::uint32_t>(b);
}

/// Union-find over vertices.
class VertexSets {
 public:
  explicit VertexSets(long size) : parent_(static_cast<std::size_t>(size)) {
    std::iota(parent_.begin(), parent_.end(), 0L);
  }
  long find(long i) {
    while (parent_[static_cast<std::size_t>(i)] != i)
      i = parent_[static_cast<std::size_t>(i)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(i)])];
    return i;
  }
  void join(long a, long b) {
    a = find(a), b = find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<long> parent_;
};

}  // namespace

std::vector<BoundaryLoop> boundary_loops(const Mesh& mesh) {
  const auto& F = mesh.F;
  // Every directed edge as its undirected key with the direction in the lowest bit
  // (min << 32 | max << 1 | (a > b); indices are non-negative ints, so max << 1 fits 32 bits).
  // Sorted, the uses of one edge are adjacent, so one linear pass finds the directed edges
  // whose reverse no face uses: those lie on a hole.
  std::vector<std::uint64_t> uses;
  uses.reserve(static_cast<std::size_t>(F.rows()) * 3);
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(F(f, k)), b = static_cast<std::uint32_t>(F(f, (k + 1) % 3));
      if (a == b) continue;  // a degenerate face's edge is its own reverse: never on a hole
      uses.push_back((std::uint64_t{std::min(a, b)} << 32) | (std::uint64_t{std::max(a, b)} << 1) | (a > b ? 1u : 0u));
    }
  std::sort(uses.begin(), uses.end());
  std::vector<std::pair<int, int>> boundary;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && (uses[j] >> 1) == (uses[i] >> 1)) ++j;
    // Sorted by direction within the run: both directions are used iff the first and last differ.
    if ((uses[i] & 1) == (uses[j - 1] & 1)) {
      const auto low = static_cast<int>(uses[i] >> 32), high = static_cast<int>((uses[i] & 0xffffffffu) >> 1);
      for (std::size_t u = i; u < j; ++u) (uses[u] & 1) ? boundary.emplace_back(high, low) : boundary.emplace_back(low, high);
    }
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());  // by source vertex, as the walk below looks them up
  std::vector<char> used(boundary.size(), 0);
  std::vector<BoundaryLoop> loops;
  for (std::size_t start = 0; start < boundary.size(); ++start) {
    if (used[start]) continue;
    BoundaryLoop loop;
    std::size_t edge = start;
    while (!used[edge]) {
      used[edge] = 1;
      const auto [a, b] = boundary[edge];
      loop.vertices.push_back(a);
      loop.perimeter += (mesh.V.row(b) - mesh.V.row(a)).norm();
      // The unused boundary edge leaving b (one on a manifold mesh without pinch vertices).
      auto next = std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(b, -1));
      while (next != boundary.end() && next->first == b && used[static_cast<std::size_t>(next - boundary.begin())]) ++next;
      if (next == boundary.end() || next->first != b) break;
      edge = static_cast<std::size_t>(next - boundary.begin());
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

SurfaceTopology surface_topology(const Mesh& mesh) {
  SurfaceTopology topology;
  const auto& F = mesh.F;
  const long n = mesh.V.rows();
  VertexSets sets(n);
  std::vector<std::uint64_t> edges;  // undirected, min << 32 | max
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      sets.join(a, b);
      edges.push_back(edge_key(std::min(a, b), std::max(a, b)));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  // Per piece (indexed by its root vertex): V − E + F and the boundary loops.
  std::vector<long> euler(static_cast<std::size_t>(n), 0), loops_of(static_cast<std::size_t>(n), 0);
  std::vector<char> referenced(static_cast<std::size_t>(n), 0);
  for (long f = 0; f < F.rows(); ++f) {
    ++euler[static_cast<std::size_t>(sets.find(F(f, 0)))];
    for (int k = 0; k < 3; ++k) referenced[static_cast<std::size_t>(F(f, k))] = 1;
  }
  for (long v = 0; v < n; ++v)
    if (referenced[static_cast<std::size_t>(v)]) ++euler[static_cast<std::size_t>(sets.find(v))];
  for (const std::uint64_t key : edges) --euler[static_cast<std::size_t>(sets.find(static_cast<long>(key >> 32)))];
  for (const BoundaryLoop& loop : boundary_loops(mesh)) {
    ++loops_of[static_cast<std::size_t>(sets.find(loop.vertices.front()))];
    ++topology.holes;
    topology.largest_hole_edges = std::max(topology.largest_hole_edges, static_cast<long>(loop.vertices.size()));
    topology.largest_hole_perimeter = std::max(topology.largest_hole_perimeter, loop.perimeter);
  }
  for (long v = 0; v < n; ++v) {
    if (!referenced[static_cast<std::size_t>(v)] || sets.find(v) != v) continue;
    ++topology.components;
    topology.genus += (2 - loops_of[static_cast<std::size_t>(v)] - euler[static_cast<std::size_t>(v)]) / 2;
  }
  return topology;
}

Mesh close_holes(const Mesh& mesh) {
  const std::vector<BoundaryLoop> loops = boundary_loops(mesh);
  if (loops.empty()) return mesh;
  long faces = mesh.F.rows();
  for (const auto& loop : loops) faces += static_cast<long>(loop.vertices.size());
  Mesh closed;
  const long n = mesh.V.rows(), holes = static_cast<long>(loops.size());
  closed.V.resize(n + holes, 3);
  closed.V.topRows(n) = mesh.V;
  if (mesh.has_colors()) {
    closed.colors.resize(n + holes, 3);
    closed.colors.topRows(n) = mesh.colors;
  }
  if (mesh.has_uvs()) {
    closed.uvs.resize(n + holes, 2);
    closed.uvs.topRows(n) = mesh.uvs;
  }
  closed.F.resize(faces, 3);
  closed.F.topRows(mesh.F.rows()) = mesh.F;
  long next_face = mesh.F.rows();
  for (long h = 0; h < holes; ++h) {
    const auto& ring = loops[static_cast<std::size_t>(h)].vertices;
    const long centre = n + h;
    auto mean = [&](const Eigen::MatrixXd& values) {
      Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(values.cols());
      for (const int v : ring) sum += values.row(v);
      return Eigen::RowVectorXd(sum / static_cast<double>(ring.size()));
    };
    closed.V.row(centre) = mean(mesh.V);
    if (mesh.has_colors()) closed.colors.row(centre) = mean(mesh.colors);
    if (mesh.has_uvs()) closed.uvs.row(centre) = mean(mesh.uvs);
    // Loop edge a→b belongs to a face running a→b: the closing face runs b→a.
    for (std::size_t k = 0; k < ring.size(); ++k)
      closed.F.row(next_face++) << ring[(k + 1) % ring.size()], ring[k], static_cast<int>(centre);
  }
  return closed;
}

}  // namespace surfcap::core
