#include "surfcap/align/root_choice.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::align {

namespace {

/// Connected components of the cross-section at height y: the crossing edges of each face that the
/// plane cuts are joined (union-find over mesh edges).
int section_components(const core::Mesh& mesh, double y) {
  std::unordered_map<std::uint64_t, int> edge_index;
  std::vector<int> parent;
  auto find = [&](int a) {
    while (parent[static_cast<std::size_t>(a)] != a) a = parent[static_cast<std::size_t>(a)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
    return a;
  };
  auto edge = [&](int a, int b) {
    const auto key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
    const auto [it, inserted] = edge_index.try_emplace(key, static_cast<int>(parent.size()));
    if (inserted) parent.push_back(it->second);
    return it->second;
  };
  for (long f = 0; f < mesh.F.rows(); ++f) {
    int crossing[3], count = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      if ((mesh.V(a, 1) > y) != (mesh.V(b, 1) > y)) crossing[count++] = edge(a, b);
    }
    if (count == 2) {
      const int ra = find(crossing[0]), rb = find(crossing[1]);
      if (ra != rb) parent[static_cast<std::size_t>(ra)] = rb;
    }
  }
  int components = 0;
  for (int i = 0; i < static_cast<int>(parent.size()); ++i) components += find(i) == i ? 1 : 0;
  return components;
}

}  // namespace

double part_separation(const core::Mesh& mesh, int slices) {
  if (mesh.vertex_count() == 0 || slices < 1) return 0;
  const double low = mesh.V.col(1).minCoeff(), high = mesh.V.col(1).maxCoeff();
  double sum = 0;
  for (int s = 0; s < slices; ++s) {
    const double t = slices == 1 ? 0.5 : 0.03 + 0.94 * s / (slices - 1);
    sum += section_components(mesh, low + t * (high - low));
  }
  return sum / slices;
}

RootCandidates root_candidates(const core::Capture& capture, const similarity::FrameList& frames, double tolerance,
                               int threads) {
  struct Node {
    int sequence, frame;
  };
  std::vector<Node> nodes;
  for (const auto& sequence : frames.sequences) {
    const int index = capture.sequence_index(sequence.name);
    if (index < 0) throw core::bad_input(capture.folder / "capture.json", "has no sequence '" + sequence.name + "'");
    for (int k = 0; k < sequence.count; ++k) nodes.push_back({index, sequence.first + k});
  }
  const long n = static_cast<long>(nodes.size());
  RootCandidates result;
  result.separation.assign(static_cast<std::size_t>(n), 0.0);
  core::parallel_for(n, threads, [&](long i) {
    const Node& node = nodes[static_cast<std::size_t>(i)];
    result.separation[static_cast<std::size_t>(i)] =
        part_separation(core::read_reconstruction(capture.mesh_path(node.sequence, node.frame), node.frame));
  });
  const double best = n > 0 ? *std::max_element(result.separation.begin(), result.separation.end()) : 0.0;
  result.candidates.assign(static_cast<std::size_t>(n), 0);
  for (long i = 0; i < n; ++i)
    result.candidates[static_cast<std::size_t>(i)] = result.separation[static_cast<std::size_t>(i)] >= best - tolerance ? 1 : 0;
  return result;
}

core::Json root_choice_json(const RootCandidates& choice) {
  const double best = choice.separation.empty() ? 0.0 : *std::max_element(choice.separation.begin(), choice.separation.end());
  return {{"separation", choice.separation},
          {"candidates", std::count(choice.candidates.begin(), choice.candidates.end(), static_cast<char>(1))},
          {"best", best}};
}

}  // namespace surfcap::align
