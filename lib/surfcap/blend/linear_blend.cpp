#include "surfcap/blend/linear_blend.hpp"

#include "surfcap/core/error.hpp"

namespace surfcap::blend {

void linear_blend_into(const std::vector<const Eigen::MatrixXd*>& meshes, const std::vector<double>& weights,
                       Eigen::MatrixXd& result) {
  if (meshes.empty() || meshes.size() != weights.size())
    throw core::internal_error("linear_blend: need one weight per mesh");
  double total = 0;
  for (double w : weights) total += w;
  if (!(total > 0)) throw core::internal_error("linear_blend: weights must have a positive sum");
  result.setZero(meshes.front()->rows(), meshes.front()->cols());
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (weights[i] != 0) result.noalias() += (weights[i] / total) * *meshes[i];
}

Eigen::MatrixXd linear_blend(const std::vector<const Eigen::MatrixXd*>& meshes, const std::vector<double>& weights) {
  Eigen::MatrixXd result;
  linear_blend_into(meshes, weights, result);
  return result;
}

}  // namespace surfcap::blend
