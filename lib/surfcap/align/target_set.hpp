#pragma once
// What every correspondence source of a pairwise alignment adds to and the deformer solves for:
// per template surface vertex a target position and a soft-constraint weight (0: no target).

#include <Eigen/Core>

namespace surfcap::align {

struct TargetSet {
  explicit TargetSet(const Eigen::MatrixXd& surface)
      : positions(surface), weights(Eigen::VectorXd::Zero(surface.rows())) {}
  Eigen::MatrixXd positions;  ///< surface×3; rows without a target keep the current position
  Eigen::VectorXd weights;    ///< relative to the mean diagonal of the Laplacian
};

}  // namespace surfcap::align
