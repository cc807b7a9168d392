#include "surfcap/blend/blend_comparison.hpp"

#include <chrono>

#include "surfcap/blend/hybrid_blend.hpp"

namespace surfcap::blend {

core::Json compare_blends(const core::Mesh& template_mesh, const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                          const BlendComparisonOptions& options) {
  using Clock = std::chrono::steady_clock;
  const NonlinearBlender blender(template_mesh);
  const SourceSet sources(blender, {{a}, {b}}, options.threads);
  std::vector<double> weights;
  for (double w = options.weight_step; w < 1.0 - 1e-9; w += options.weight_step) weights.push_back(w);
  std::vector<Eigen::MatrixXd> exact;
  const auto exact_start = Clock::now();
  for (double w : weights) exact.push_back(sources.exact(0, {w}));
  const double exact_seconds = std::chrono::duration<double>(Clock::now() - exact_start).count() / weights.size();
  const double height = template_mesh.V.col(1).maxCoeff() - template_mesh.V.col(1).minCoeff();

  HybridOptions hybrid_options;
  hybrid_options.tolerance_m = options.tolerance_m;
  hybrid_options.threads = options.threads;
  const HybridBlend one = HybridBlend::with_breakpoints(sources, {{0.5}}, hybrid_options);
  const HybridBlend three = HybridBlend::with_breakpoints(sources, {{0.25, 0.5, 0.75}}, hybrid_options);

  core::Json methods = core::Json::array();
  auto row = [&](const std::string& name, long references, const auto& evaluate) {
    double error = 0;
    Eigen::MatrixXd mesh;
    const int repeats = 200;
    const auto start = Clock::now();
    for (int r = 0; r < repeats; ++r)
      for (double w : weights) evaluate(w, mesh);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count() / (repeats * weights.size());
    for (std::size_t i = 0; i < weights.size(); ++i) {
      evaluate(weights[i], mesh);
      error = std::max(error, (mesh - exact[i]).rowwise().norm().maxCoeff());
    }
    methods.push_back({{"method", name}, {"references", references}, {"max_error_m", error},
                       {"max_error_percent", 100 * error / height}, {"seconds_per_frame", seconds}});
  };
  row("linear", 0, [&](double w, Eigen::MatrixXd& mesh) { sources.linear_into(0, {w}, mesh); });
  row("hybrid_1", 1, [&](double w, Eigen::MatrixXd& mesh) { one.evaluate_into(sources, 0, {w}, mesh); });
  row("hybrid_3", 3, [&](double w, Eigen::MatrixXd& mesh) { three.evaluate_into(sources, 0, {w}, mesh); });
  methods.push_back({{"method", "nonlinear"}, {"references", 0}, {"max_error_m", 0.0}, {"max_error_percent", 0.0},
                     {"seconds_per_frame", exact_seconds}});
  return {{"model_height_m", height}, {"vertices", template_mesh.V.rows()}, {"faces", template_mesh.F.rows()},
          {"weight_step", options.weight_step}, {"methods", methods}};
}

}  // namespace surfcap::blend
