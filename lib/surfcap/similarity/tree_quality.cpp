#include "surfcap/similarity/tree_quality.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::similarity {

Eigen::MatrixXd ground_truth_distances(const core::AlignedDatabase& truth, const FrameList& frames, int threads) {
  std::vector<const Eigen::MatrixXd*> surfaces;
  for (const auto& sequence : frames.sequences) {
    const int s = truth.sequence_index(sequence.name);
    if (s < 0) throw core::bad_input("ground truth", "has no sequence '" + sequence.name + "'");
    const auto& frames_of = truth.sequences[static_cast<std::size_t>(s)].frames;
    if (static_cast<int>(frames_of.size()) < sequence.count)
      throw core::bad_input("ground truth", "sequence '" + sequence.name + "' has " + std::to_string(frames_of.size()) +
                                                " frames, the capture " + std::to_string(sequence.count));
    for (int f = 0; f < sequence.count; ++f) surfaces.push_back(&frames_of[static_cast<std::size_t>(f)]);
  }
  const long n = static_cast<long>(surfaces.size());
  Eigen::MatrixXd distances = Eigen::MatrixXd::Zero(n, n);
  core::parallel_for(n, threads, [&](long i) {
    for (long j = i + 1; j < n; ++j)
      distances(i, j) = (*surfaces[static_cast<std::size_t>(i)] - *surfaces[static_cast<std::size_t>(j)]).rowwise().norm().mean();
  });
  distances.triangularView<Eigen::StrictlyLower>() = distances.transpose();
  return distances;
}

TreeQuality tree_quality(const SimilarityTree& tree, const Eigen::MatrixXd& true_distances) {
  TreeQuality quality;
  for (const auto& edge : tree.edges) quality.tree_deformation += true_distances(edge.parent, edge.child);
  quality.optimal_deformation = minimum_spanning_tree_cost(true_distances);
  quality.ratio = quality.optimal_deformation > 0 ? quality.tree_deformation / quality.optimal_deformation : 1.0;
  return quality;
}

}  // namespace surfcap::similarity
