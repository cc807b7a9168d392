#pragma once
// casas2011 Table 1: max vertex error of linear and hybrid (1 and 3 references) blending of two
// poses against the exact non-linear blend, as % of model height, with times per frame.
#include <Eigen/Core>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::blend {

struct BlendComparisonOptions {
  double weight_step = 0.05;   ///< errors are the max over w = step, 2·step, …, 1 − step
  double tolerance_m = 0.005;  ///< only sets the sparsity threshold (ε·0.1) of the stored fields
  int threads = 1;
};

/// {"model_height_m", "vertices", "methods": [{"method", "references", "max_error_m",
/// "max_error_percent", "seconds_per_frame"}]} for linear, hybrid_1, hybrid_3, nonlinear.
core::Json compare_blends(const core::Mesh& template_mesh, const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                          const BlendComparisonOptions& options = {});

}  // namespace surfcap::blend
