#pragma once
// Transition similarity between two motion spaces (casas2013 §3.2.1–3.2.2):
//   d(M_i, M_j) = (‖X_i − X_j‖² + λ‖V_i − V_j‖²) / N_v,   s = 1 − d / max d,
// between every frame of every reference sequence (grid node of the hybrid blend: the sources and
// the bisection references, M_L(t, w_j) + D_NL(t, w_j)) of `from` and of `to`. Rows are
// node·T_from + t, columns node·T_to + t, as the runtime's eq. 5 lower bound indexes them.
#include <Eigen/Core>
#include <vector>

#include "surfcap/blend/stored_space.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::graph {

using FeatureMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct TransitionOptions {
  /// λ of d: weight of the velocity term; velocities are in metres per captured frame (1/fps).
  double velocity_weight = 1.0;
  int threads = 0;  ///< 0: all hardware threads; the result does not depend on it
  void validate() const;
};

/// Per reference frame of a space, the features compared by d: body-frame positions X (centred
/// mesh + the blended root height) and velocities V (backward difference; forward at t = 0, plus the
/// blended root velocity turned into the body frame). Row node·T + t; columns [X (3V) | √λ·V (3V)].
FeatureMatrix reference_features(const blend::StoredSpace& space, double velocity_weight, int threads = 0);

/// The centred mesh of grid node `node` at normalised frame t: Σ_i w_i(u_node) X_i(t) + D_NL(node, t).
Eigen::MatrixXd reference_frame(const blend::StoredSpace& space, long node, int t);

struct TransitionSimilarity {
  long rows = 0, cols = 0;
  std::vector<float> similarity;  ///< row-major [rows][cols], in [0, 1]
  double max_distance = 0;        ///< max d (m² per vertex), the normaliser
  core::Json figures = core::Json::object();  ///< for the report: statistics, best pair, timings
};

/// s between every reference frame of `from` and of `to` (same vertex count).
TransitionSimilarity transition_similarity(const blend::StoredSpace& from, const blend::StoredSpace& to,
                                           const TransitionOptions& options);

}  // namespace surfcap::graph
