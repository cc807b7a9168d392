#pragma once
// Linear vertex blending (casas2011 §4.1): M_L = Σ w_i M_i / Σ w_i.
#include <Eigen/Core>
#include <vector>

namespace surfcap::blend {

/// Weighted average of `meshes` (each n×3, same n). Weights need not sum to one but must have a
/// positive sum; zero-weight meshes are skipped.
Eigen::MatrixXd linear_blend(const std::vector<const Eigen::MatrixXd*>& meshes, const std::vector<double>& weights);

/// Same, writing into `result` (resized if needed) without allocating when it has the right size.
void linear_blend_into(const std::vector<const Eigen::MatrixXd*>& meshes, const std::vector<double>& weights,
                       Eigen::MatrixXd& result);

}  // namespace surfcap::blend
