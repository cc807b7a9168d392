#include "surfcap/blend/source_set.hpp"

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::blend {

std::vector<double> corner_weights(const std::vector<double>& u) {
  const std::size_t corners = std::size_t{1} << u.size();
  std::vector<double> weights(corners, 1.0);
  for (std::size_t i = 0; i < corners; ++i)
    for (std::size_t a = 0; a < u.size(); ++a) weights[i] *= ((i >> a) & 1U) ? u[a] : 1.0 - u[a];
  return weights;
}

int weight_space_dimensions(int source_count) {
  for (int d = 1; d <= 3; ++d)
    if (source_count == (1 << d)) return d;
  throw core::bad_arguments("a motion space needs 2, 4 or 8 sequences (the corners of its weight space), got " +
                            std::to_string(source_count));
}

SourceSet::SourceSet(const NonlinearBlender& blender, std::vector<std::vector<Eigen::MatrixXd>> frames, int threads)
    : blender_(&blender), frames_(std::move(frames)) {
  dimensions_ = weight_space_dimensions(static_cast<int>(frames_.size()));
  const std::size_t T = frames_.front().size();
  if (T == 0) throw core::bad_arguments("a motion space needs at least one frame");
  for (const auto& source : frames_)
    if (source.size() != T) throw core::internal_error("SourceSet: sources must have the same frame count");
  decomposed_.assign(frames_.size(), std::vector<DecomposedFrame>(T));
  const long total = static_cast<long>(frames_.size() * T);
  core::parallel_for(total, threads, [&](long index) {
    const std::size_t i = static_cast<std::size_t>(index) / T, t = static_cast<std::size_t>(index) % T;
    decomposed_[i][t] = blender_->decompose(frames_[i][t]);
  });
}

void SourceSet::linear_into(int t, const std::vector<double>& u, Eigen::MatrixXd& result) const {
  const std::vector<double> w = corner_weights(u);
  result.setZero(vertex_count(), 3);
  for (std::size_t i = 0; i < w.size(); ++i)
    if (w[i] != 0) result.noalias() += w[i] * frames_[i][t];
}

Eigen::MatrixXd SourceSet::linear(int t, const std::vector<double>& u) const {
  Eigen::MatrixXd result;
  linear_into(t, u, result);
  return result;
}

Eigen::MatrixXd SourceSet::exact(int t, const std::vector<double>& u, int threads) const {
  const std::vector<double> w = corner_weights(u);
  for (std::size_t i = 0; i < w.size(); ++i)
    if (w[i] == 1.0) return frames_[i][t];
  std::vector<const DecomposedFrame*> pointers;
  for (const auto& source : decomposed_) pointers.push_back(&source[static_cast<std::size_t>(t)]);
  return blender_->blend(pointers, w, threads);
}

}  // namespace surfcap::blend
