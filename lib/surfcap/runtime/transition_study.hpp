#pragma once
// casas2013 Table 2: online trellis planning against a fixed set of the n best precomputed
// transitions, over random start and end states (docs/runtime.md). With fixed transitions the
// character keeps playing the source space (parameters ramping at Δp per frame) until it reaches
// the source frame of one of them, jumps to its target frame and plays on to the target state;
// the one of least E_S + λE_L among the reachable ones is taken.
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/runtime/transition_planner.hpp"

namespace surfcap::runtime {

/// A precomputed transition between two reference frames (grid node, normalised frame).
struct FixedTransition {
  double similarity = 0;
  double from_frame = 0, to_frame = 0;
  std::vector<double> from_parameters, to_parameters;  ///< parameters of the nodes' weights
};

/// The `count` most similar entries of the planner's matrix with distinct source frames.
std::vector<FixedTransition> best_fixed_transitions(const TransitionPlanner& planner, int count);

/// The cheapest reachable fixed transition from `source` to `target`; `reachable` false (and an
/// infinite cost) when none is.
TransitionPlan plan_fixed(const TransitionPlanner& planner, const std::vector<FixedTransition>& transitions,
                          const MotionState& source, const MotionState& target, bool& reachable);

struct StudyOptions {
  int transitions = 50;              ///< random (source, target) state pairs
  std::vector<int> depths{12, 10};   ///< online trellis depths
  std::vector<int> fixed{1, 5, 10};  ///< numbers of precomputed transitions
  unsigned seed = 2013;
  int repeats = 100;                 ///< timing repetitions of the whole set
};

/// Runs the comparison from space `from` to space `to`; rows per method with the means of E_S,
/// λE_L, latency (s), planning time (s) and the offline selection time (s).
core::Json transition_study(const asset::Character& character, const std::string& from, const std::string& to,
                            const PlannerOptions& planner_options, const StudyOptions& options);

}  // namespace surfcap::runtime
