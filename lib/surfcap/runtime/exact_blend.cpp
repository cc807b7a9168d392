#include "surfcap/runtime/exact_blend.hpp"

#include <cmath>

#include "surfcap/core/parallel.hpp"

namespace surfcap::runtime {

ExactBlend::ExactBlend(const asset::Character& character, int threads)
    : character_(&character), blender_(std::make_unique<blend::NonlinearBlender>(character.template_mesh)) {
  const long V = character.vertex_count();
  for (const asset::CharacterSpace& space : character.spaces) {
    evaluators_.push_back(std::make_unique<SpaceEvaluator>(space));
    const int N = space.source_count(), T = space.frames;
    std::vector<std::vector<blend::DecomposedFrame>> frames(static_cast<std::size_t>(N),
                                                            std::vector<blend::DecomposedFrame>(static_cast<std::size_t>(T)));
    core::parallel_for(static_cast<long>(N) * T, threads, [&](long index) {
      const float* x = space.references.data() + static_cast<std::size_t>(index) * V * 3;
      Eigen::MatrixXd mesh(V, 3);
      for (long v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c) mesh(v, c) = x[v * 3 + c];
      frames[index / T][index % T] = blender_->decompose(mesh);
    });
    decomposed_.push_back(std::move(frames));
  }
}

ExactBlend::~ExactBlend() = default;

Eigen::MatrixXd ExactBlend::centred(int space, double frame, const std::vector<double>& u) const {
  const SpaceEvaluator& evaluator = *evaluators_[space];
  const int T = evaluator.frames();
  const double f = evaluator.wrap(frame);
  const int k0 = std::min(static_cast<int>(f), T - 1);
  const double alpha = f - k0;
  const int k1 = evaluator.cyclic() ? (k0 + 1) % T : std::min(k0 + 1, T - 1);
  std::vector<double> w(static_cast<std::size_t>(1 << evaluator.dimensions()));
  evaluator.source_weights(u.data(), w.data());
  const auto blend_at = [&](int k) {
    std::vector<const blend::DecomposedFrame*> frames;
    for (std::size_t i = 0; i < w.size(); ++i) frames.push_back(&decomposed_[space][i][k]);
    return blender_->blend(frames, w);
  };
  Eigen::MatrixXd result = blend_at(k0);
  if (alpha > 0 && k1 != k0) result = (1 - alpha) * result + alpha * blend_at(k1);
  return result;
}

double max_vertex_error(const std::vector<float>& mesh, const Eigen::MatrixXd& reference) {
  double worst = 0;
  for (long v = 0; v < reference.rows(); ++v) {
    const double dx = mesh[v * 3] - reference(v, 0), dy = mesh[v * 3 + 1] - reference(v, 1),
                 dz = mesh[v * 3 + 2] - reference(v, 2);
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return worst;
}

}  // namespace surfcap::runtime
