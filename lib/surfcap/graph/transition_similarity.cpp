#include "surfcap/graph/transition_similarity.hpp"

#include <chrono>
#include <cmath>

#include "surfcap/blend/source_set.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::graph {
namespace {

/// Σ_i w_i root_i(t) in the body frame of each source: (height y, body-frame root velocity per
/// normalised frame x, y, z). t = 0 uses the forward difference.
Eigen::Vector4d blended_root(const blend::StoredSpace& space, const std::vector<double>& w, int t) {
  const int T = space.frames;
  const int a = t == 0 ? 0 : t - 1, b = t == 0 ? 1 : t;
  Eigen::Vector4d result = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0) continue;
    const float* ra = space.root_motion.data() + (i * T + a) * 4;
    const float* rb = space.root_motion.data() + (i * T + b) * 4;
    const float* now = space.root_motion.data() + (i * T + t) * 4;
    const double dx = rb[0] - ra[0], dy = rb[1] - ra[1], dz = rb[2] - ra[2];
    const double c = std::cos(rb[3]), s = std::sin(rb[3]);
    // R_y(−heading)·d: the world displacement seen from the body.
    result += w[i] * Eigen::Vector4d(now[1], c * dx - s * dz, dy, s * dx + c * dz);
  }
  return result;
}

double blended_duration(const blend::StoredSpace& space, const std::vector<double>& w) {
  double duration = 0;
  for (std::size_t i = 0; i < w.size(); ++i) duration += w[i] * space.sources[i].duration_s;
  return duration;
}

}  // namespace

void TransitionOptions::validate() const {
  if (!(velocity_weight >= 0) || !std::isfinite(velocity_weight))
    throw core::bad_arguments("--velocity-weight must be a finite number ≥ 0");
}

Eigen::MatrixXd reference_frame(const blend::StoredSpace& space, long node, int t) {
  const long V = space.vertex_count();
  const int T = space.frames;
  const std::vector<double> w = blend::corner_weights(space.node_coordinates[node]);
  Eigen::MatrixXd mesh = Eigen::MatrixXd::Zero(V, 3);
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0) continue;
    const float* x = space.references.data() + (i * T + t) * V * 3;
    for (long v = 0; v < V; ++v)
      for (int c = 0; c < 3; ++c) mesh(v, c) += w[i] * x[v * 3 + c];
  }
  const std::size_t row = static_cast<std::size_t>(node) * T + t;
  for (auto k = space.displacement_offsets[row]; k < space.displacement_offsets[row + 1]; ++k)
    for (int c = 0; c < 3; ++c)
      mesh(space.displacement_vertices[k], c) += core::half_to_float(space.displacement_values[k * 3 + c]);
  return mesh;
}

FeatureMatrix reference_features(const blend::StoredSpace& space, double velocity_weight, int threads) {
  const long V = space.vertex_count(), R = space.node_count();
  const int T = space.frames;
  const double fps = (space.sources.front().frames - 1) / std::max(1e-9, space.sources.front().duration_s);
  FeatureMatrix features(R * T, 6 * V);
  const double root_weight = std::sqrt(velocity_weight);
  core::parallel_for(R, threads, [&](long node) {
    const std::vector<double> w = blend::corner_weights(space.node_coordinates[node]);
    // Normalised frames per captured frame: velocities in metres per 1/fps seconds.
    const double per_frame = (T - 1) / std::max(1e-9, blended_duration(space, w) * fps);
    std::vector<Eigen::MatrixXd> frames(static_cast<std::size_t>(T));
    for (int t = 0; t < T; ++t) frames[t] = reference_frame(space, node, t);
    for (int t = 0; t < T; ++t) {
      const Eigen::Vector4d root = blended_root(space, w, t);
      const Eigen::MatrixXd& previous = frames[t == 0 ? 0 : t - 1];
      const Eigen::MatrixXd& next = frames[t == 0 ? 1 : t];
      auto row = features.row(node * T + t);
      for (long v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c) {
          row(v * 3 + c) = frames[t](v, c) + (c == 1 ? root(0) : 0.0);
          row(3 * V + v * 3 + c) = root_weight * per_frame * (next(v, c) - previous(v, c) + root(1 + c));
        }
    }
  });
  return features;
}

TransitionSimilarity transition_similarity(const blend::StoredSpace& from, const blend::StoredSpace& to,
                                           const TransitionOptions& options) {
  options.validate();
  if (from.vertex_count() != to.vertex_count())
    throw core::bad_input("space '" + to.name + "'", "has " + std::to_string(to.vertex_count()) + " vertices, space '" +
                                                         from.name + "' " + std::to_string(from.vertex_count()));
  using Clock = std::chrono::steady_clock;
  auto start = Clock::now();
  const FeatureMatrix a = reference_features(from, options.velocity_weight, options.threads);
  const FeatureMatrix b = reference_features(to, options.velocity_weight, options.threads);
  const double features_s = std::chrono::duration<double>(Clock::now() - start).count();
  start = Clock::now();
  const Eigen::VectorXd a_norms = a.rowwise().squaredNorm(), b_norms = b.rowwise().squaredNorm();
  const double inverse_vertices = 1.0 / static_cast<double>(from.vertex_count());
  TransitionSimilarity result;
  result.rows = a.rows();
  result.cols = b.rows();
  // Gram form ‖a − b‖² = ‖a‖² + ‖b‖² − 2 a·b. The Gram matrix A·Bᵀ is computed in 4×4 tiles over
  // fixed 2,048-wide slices of the features, each tile a GEMM too small for Eigen to thread (one
  // panel of nr columns), the tiles of a row block in parallel: every entry is summed in the same
  // order whatever the thread count, so the bytes are the same.
  constexpr long kTile = 4, kSlice = 2048;
  Eigen::MatrixXd gram(result.rows, result.cols);
  const long blocks = (result.rows + kTile - 1) / kTile;
  core::parallel_for(blocks, options.threads, [&](long block) {
    const long first = block * kTile, count = std::min(kTile, result.rows - first);
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(count, result.cols);
    for (long k = 0; k < a.cols(); k += kSlice) {
      const long width = std::min(kSlice, a.cols() - k);
      const auto rows = a.block(first, k, count, width);
      for (long j = 0; j < result.cols; j += kTile) {
        const long columns = std::min(kTile, result.cols - j);
        local.middleCols(j, columns).noalias() += rows * b.block(j, k, columns, width).transpose();
      }
    }
    gram.middleRows(first, count) = local;
  });
  Eigen::MatrixXd distance(result.rows, result.cols);
  for (long i = 0; i < result.rows; ++i)
    for (long j = 0; j < result.cols; ++j)
      distance(i, j) = std::max(0.0, a_norms(i) + b_norms(j) - 2.0 * gram(i, j)) * inverse_vertices;
  result.max_distance = distance.maxCoeff();
  const double scale = result.max_distance > 0 ? 1.0 / result.max_distance : 0.0;
  result.similarity.resize(static_cast<std::size_t>(result.rows * result.cols));
  for (long i = 0; i < result.rows; ++i)
    for (long j = 0; j < result.cols; ++j)
      result.similarity[static_cast<std::size_t>(i * result.cols + j)] = static_cast<float>(1.0 - distance(i, j) * scale);
  const double gram_s = std::chrono::duration<double>(Clock::now() - start).count();

  Eigen::Index best_row = 0, best_col = 0;
  const double best_distance = distance.minCoeff(&best_row, &best_col);
  const auto node_frame = [](long index, int frames) {
    return core::Json{{"node", index / frames}, {"frame", index % frames}};
  };
  result.figures = {{"rows", result.rows}, {"cols", result.cols}, {"vertices", from.vertex_count()},
                    {"velocity_weight", options.velocity_weight}, {"max_distance_m2", result.max_distance},
                    {"min_distance_m2", best_distance},
                    {"mean_similarity", 1.0 - distance.mean() * scale},
                    {"best", {{"similarity", 1.0 - best_distance * scale}, {"from", node_frame(best_row, from.frames)},
                              {"to", node_frame(best_col, to.frames)}}},
                    {"timings_s", {{"features", features_s}, {"distances", gram_s}}}};
  return result;
}

}  // namespace surfcap::graph
