#pragma once
// Online transition planning between two motion spaces (casas2013 §3.2.2, eqs. 4–5):
//   P_opt = argmin_P E_S(P) + λ E_L(P),
// over a trellis sampled forward in time from the current state in the source space and backward
// in time from the target state in the target space (depth l_max, one output frame Δt per level,
// parameters changing by at most Δp per level), with a transition between every pair of trellis
// nodes. E_S = scale·(1 − s_lb), s_lb the weighted lower bound of eq. 5 from the precomputed
// reference similarity matrix; E_L = the frames of the path (source levels + target levels).
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/runtime/space_evaluator.hpp"

namespace surfcap::runtime {

/// Where the character is: a space, a fractional normalised frame and the space's parameters.
struct MotionState {
  int space = 0;
  double frame = 0;
  std::vector<double> parameters;  ///< high-level values (or u when the space has no parameter map)
};

struct PlannerOptions {
  int depth = 10;                    ///< l_max, trellis levels on each side
  double latency_weight = 5.0;       ///< λ (casas2013: 5)
  double parameter_step = 0.1;       ///< Δp as a fraction of each parameter's range (casas2013: 0.1)
  double similarity_scale = 1000.0;  ///< E_S = scale·(1 − s): per-mille dissimilarity, commensurate with λ per frame
  double fps = 25.0;                 ///< output frames per second (Δt = 1/fps)
  void validate() const;
};

struct TransitionPlan {
  /// States to play after the current one: `source_steps` in the source space, then
  /// `target_steps` + 1 in the target space ending at the target state.
  std::vector<MotionState> frames;
  int source_steps = 0;
  int target_steps = 0;
  double similarity = 0;       ///< s_lb at the transition
  double similarity_cost = 0;  ///< E_S
  double latency_cost = 0;     ///< λ E_L, E_L = source_steps + target_steps
  long evaluated_pairs = 0;    ///< transition candidates whose similarity was evaluated
  double cost() const { return similarity_cost + latency_cost; }
};

class TransitionPlanner {
 public:
  /// `similarity` is the from → to matrix (rows node·T_from + t, columns node·T_to + t).
  TransitionPlanner(const SpaceEvaluator& from, const SpaceEvaluator& to, const asset::CharacterTransition& similarity,
                    const PlannerOptions& options);

  /// The cheapest path from `source` (a state of `from`) to `target` (a state of `to`). Not
  /// thread-safe (reuses scratch buffers); one planner per thread.
  TransitionPlan plan(const MotionState& source, const MotionState& target) const;
  /// Same without building the frame list (cost, steps, similarity only): the hot part.
  TransitionPlan plan_cost(const MotionState& source, const MotionState& target) const;

  /// s_lb of eq. 5 between (f_a, u_a) of `from` and (f_b, u_b) of `to`, frames rounded to the
  /// nearest normalised frame.
  double similarity_bound(double from_frame, const double* from_u, double to_frame, const double* to_u) const;

  const PlannerOptions& options() const { return options_; }
  const SpaceEvaluator& from() const { return *from_; }
  const SpaceEvaluator& to() const { return *to_; }
  const asset::CharacterTransition& matrix() const { return *similarity_; }

 private:
  /// One trellis level's node: ≤ 2^d (matrix index, weight) entries and the parameters.
  struct Node {
    int depth = 0;
    int entries = 0;
    long index[8];
    double weight[8];
    double parameters[3];
    double bound = 1;  // Σ weight · (best similarity of the entry's row/column): s ≤ bound
  };
  struct Side {
    std::vector<Node> nodes;       // sorted by depth
    std::vector<int> depth_start;  // nodes of depth k: [depth_start[k], depth_start[k + 1])
    int levels = 0;                // deepest level + 1
    double step = 0;               // normalised frames per output frame
  };
  void build_side(const SpaceEvaluator& space, const MotionState& state, bool forward,
                  const std::vector<float>& best_of_entry, Side& side) const;
  TransitionPlan search(const MotionState& source, const MotionState& target, int& best_a, int& best_b) const;

  const SpaceEvaluator* from_;
  const SpaceEvaluator* to_;
  const asset::CharacterTransition* similarity_;
  PlannerOptions options_;
  double max_similarity_ = 1;
  std::vector<float> row_max_, col_max_;  // best similarity per matrix row / column
  mutable Side source_side_, target_side_;
  mutable std::vector<Node> combos_;
  mutable std::vector<double> axis_values_[3];
  mutable std::vector<int> axis_depths_[3];
};

}  // namespace surfcap::runtime
