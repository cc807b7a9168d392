#include "surfcap/evaluation/truth_outputs.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "surfcap/core/npy.hpp"
#include "surfcap/evaluation/alignment_report.hpp"

namespace surfcap::evaluation {

void write_truth_arrays(const std::filesystem::path& folder, const TruthReference& truth,
                        const align::Registration& registration, const TruthEvaluation& evaluation) {
  const std::size_t nodes = registration.frames.size();
  const auto n = static_cast<std::size_t>(truth.vertex_count());
  std::vector<float> errors;
  errors.reserve(nodes * n * 3);
  std::vector<std::uint8_t> observed;
  observed.reserve(nodes * n);
  for (std::size_t node = 0; node < nodes; ++node) {
    const auto& record = registration.frames[node];
    const Eigen::MatrixXd expected = truth.positions(record.sequence, record.frame);
    const Eigen::MatrixXd error = registration.world_positions[node].topRows(expected.rows()) - expected;
    for (std::size_t v = 0; v < n; ++v) {
      for (int k = 0; k < 3; ++k) errors.push_back(static_cast<float>(error(static_cast<Eigen::Index>(v), k)));
      observed.push_back(evaluation.frames[node].observed[v] ? 1 : 0);
    }
  }
  core::write_npy(folder / "truth_errors.npy", errors.data(), {nodes, n, 3});
  core::write_npy(folder / "truth_observed.npy", observed.data(), {nodes, n});
}

std::vector<long> worst_frames(const TruthEvaluation& evaluation, int count) {
  std::vector<long> order(evaluation.frames.size());
  std::iota(order.begin(), order.end(), 0L);
  std::stable_sort(order.begin(), order.end(), [&](long a, long b) {
    return evaluation.frames[static_cast<std::size_t>(a)].rms > evaluation.frames[static_cast<std::size_t>(b)].rms;
  });
  order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(std::max(count, 0))));
  return order;
}

void write_truth_preview(const std::filesystem::path& path, const TruthReference& truth,
                         const align::Registration& registration, const TruthEvaluation& evaluation, int count,
                         double scale) {
  const std::vector<long> nodes = worst_frames(evaluation, count);
  std::vector<Eigen::VectorXd> errors;
  for (const long node : nodes) {
    const auto& record = registration.frames[static_cast<std::size_t>(node)];
    const Eigen::MatrixXd expected = truth.positions(record.sequence, record.frame);
    Eigen::VectorXd error = Eigen::VectorXd::Zero(registration.database.template_mesh.vertex_count());
    error.head(expected.rows()) =
        (registration.world_positions[static_cast<std::size_t>(node)].topRows(expected.rows()) - expected).rowwise().norm();
    errors.push_back(error);
  }
  write_value_preview(path, registration, nodes, errors, scale, "from the true position");
}

}  // namespace surfcap::evaluation
