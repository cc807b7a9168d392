#include "surfcap/runtime/transition_study.hpp"

#include <algorithm>
#include <ctime>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "surfcap/core/error.hpp"

namespace surfcap::runtime {
namespace {

/// Process CPU time in seconds (the study runs on one thread; the machine may be shared).
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// Frames to play from frame `from` to frame `to` at `step` normalised frames per frame while the
/// parameters ramp by `ramp` frames; −1 when a one-shot space cannot do it.
long frames_between(const SpaceEvaluator& space, double from, double to, double step, long ramp) {
  double span = to - from;
  if (space.cyclic()) span = std::fmod(span + space.frames(), static_cast<double>(space.frames()));
  if (span < -1e-9) return -1;
  long frames = static_cast<long>(std::ceil(std::max(0.0, span) / step - 1e-9));
  if (frames >= ramp) return frames;
  if (!space.cyclic()) return -1;
  const double cycle = space.frames() / step;
  return frames + static_cast<long>(std::ceil((ramp - frames) / cycle)) * static_cast<long>(std::ceil(cycle));
}

long ramp_frames(const SpaceEvaluator& space, const std::vector<double>& a, const std::vector<double>& b, double fraction) {
  long frames = 0;
  for (int k = 0; k < space.dimensions(); ++k) {
    const double delta = fraction * (space.parameter_max(k) - space.parameter_min(k));
    if (delta > 0) frames = std::max(frames, static_cast<long>(std::ceil(std::abs(a[k] - b[k]) / delta - 1e-9)));
  }
  return frames;
}

double step_at(const SpaceEvaluator& space, const std::vector<double>& parameters, double fps) {
  std::vector<double> u(parameters.size());
  space.weight_coordinates(parameters.data(), u.data());
  return space.frames_per_step(u.data(), fps);
}

/// A random state: cyclic spaces anywhere in the cycle; one-shot spaces in their first half as a
/// source (there is still motion to leave from) and their second half as a target.
MotionState random_state(const SpaceEvaluator& space, int index, bool target, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double r = uniform(random);
  const double frame = space.cyclic() ? r * space.frames() : (target ? 0.5 + 0.5 * r : 0.5 * r) * (space.frames() - 1);
  MotionState state{index, frame, std::vector<double>(static_cast<std::size_t>(space.dimensions()))};
  for (int a = 0; a < space.dimensions(); ++a)
    state.parameters[a] = space.parameter_min(a) + uniform(random) * (space.parameter_max(a) - space.parameter_min(a));
  return state;
}

}  // namespace

std::vector<FixedTransition> best_fixed_transitions(const TransitionPlanner& planner, int count) {
  const asset::CharacterTransition& matrix = planner.matrix();
  std::vector<long> order(matrix.similarity.size());
  std::iota(order.begin(), order.end(), 0L);
  std::stable_sort(order.begin(), order.end(), [&](long a, long b) { return matrix.similarity[a] > matrix.similarity[b]; });
  const int from_frames = planner.from().frames(), to_frames = planner.to().frames();
  std::vector<FixedTransition> chosen;
  std::vector<bool> used(static_cast<std::size_t>(from_frames), false);
  for (long entry : order) {
    if (static_cast<int>(chosen.size()) >= count) break;
    const long row = entry / matrix.cols, col = entry % matrix.cols;
    if (used[row % from_frames]) continue;
    used[row % from_frames] = true;
    FixedTransition transition;
    transition.similarity = matrix.similarity[entry];
    transition.from_frame = static_cast<double>(row % from_frames);
    transition.to_frame = static_cast<double>(col % to_frames);
    transition.from_parameters = planner.from().parameters_for(planner.from().space().node_coordinates[row / from_frames]);
    transition.to_parameters = planner.to().parameters_for(planner.to().space().node_coordinates[col / to_frames]);
    chosen.push_back(std::move(transition));
  }
  return chosen;
}

TransitionPlan plan_fixed(const TransitionPlanner& planner, const std::vector<FixedTransition>& transitions,
                          const MotionState& source, const MotionState& target, bool& reachable) {
  const PlannerOptions& options = planner.options();
  const double source_step = step_at(planner.from(), source.parameters, options.fps);
  const double target_step = step_at(planner.to(), target.parameters, options.fps);
  TransitionPlan best;
  double best_cost = std::numeric_limits<double>::infinity();
  reachable = false;
  for (const FixedTransition& transition : transitions) {
    const long before = frames_between(planner.from(), source.frame, transition.from_frame, source_step,
                                       ramp_frames(planner.from(), source.parameters, transition.from_parameters,
                                                   options.parameter_step));
    const long after = frames_between(planner.to(), transition.to_frame, target.frame, target_step,
                                      ramp_frames(planner.to(), transition.to_parameters, target.parameters,
                                                  options.parameter_step));
    if (before < 0 || after < 0) continue;
    TransitionPlan plan;
    plan.similarity = transition.similarity;
    plan.source_steps = static_cast<int>(before);
    plan.target_steps = static_cast<int>(after);
    plan.similarity_cost = options.similarity_scale * (1 - transition.similarity);
    plan.latency_cost = options.latency_weight * static_cast<double>(before + after);
    plan.evaluated_pairs = 1;
    if (plan.cost() < best_cost) {
      best_cost = plan.cost();
      best = plan;
      reachable = true;
    }
  }
  return best;
}

core::Json transition_study(const asset::Character& character, const std::string& from, const std::string& to,
                            const PlannerOptions& planner_options, const StudyOptions& options) {
  const asset::CharacterTransition* matrix = character.find_transition(from, to);
  if (!matrix) throw core::bad_arguments("the character has no transition " + from + " → " + to);
  const int a = character.space_index(from), b = character.space_index(to);
  const SpaceEvaluator source_space(character.spaces[a]), target_space(character.spaces[b]);
  std::mt19937 random(options.seed);
  std::vector<std::pair<MotionState, MotionState>> pairs;
  for (int k = 0; k < options.transitions; ++k) {
    MotionState source = random_state(source_space, a, false, random);
    MotionState target = random_state(target_space, b, true, random);
    pairs.emplace_back(std::move(source), std::move(target));
  }
  core::Json rows = core::Json::array();
  const auto summarise = [&](const std::string& method, const std::vector<TransitionPlan>& plans, double online_s,
                             double offline_s, int unreachable) {
    double similarity = 0, latency = 0, frames = 0;
    for (const TransitionPlan& plan : plans) {
      similarity += plan.similarity_cost;
      latency += plan.latency_cost;
      frames += plan.source_steps + plan.target_steps;
    }
    const double n = std::max<std::size_t>(1, plans.size());
    rows.push_back({{"method", method}, {"similarity_cost", similarity / n}, {"latency_cost", latency / n},
                    {"latency_s", frames / n / planner_options.fps}, {"online_s", online_s}, {"offline_s", offline_s},
                    {"transitions", plans.size()}, {"unreachable", unreachable}});
  };
  for (int depth : options.depths) {
    PlannerOptions planner_at = planner_options;
    planner_at.depth = depth;
    const TransitionPlanner planner(source_space, target_space, *matrix, planner_at);
    std::vector<TransitionPlan> plans;
    for (const auto& [source, target] : pairs) plans.push_back(planner.plan_cost(source, target));
    const double start = cpu_seconds();
    double sink = 0;
    for (int r = 0; r < options.repeats; ++r)
      for (const auto& [source, target] : pairs) sink += planner.plan_cost(source, target).similarity;
    const double online = (cpu_seconds() - start) /
                          std::max(1.0, static_cast<double>(options.repeats) * pairs.size());
    summarise("online depth " + std::to_string(depth) + (sink < 0 ? " " : ""), plans, online, 0.0, 0);
  }
  const TransitionPlanner planner(source_space, target_space, *matrix, planner_options);
  for (int count : options.fixed) {
    double start = cpu_seconds();
    const std::vector<FixedTransition> fixed = best_fixed_transitions(planner, count);
    const double offline = cpu_seconds() - start;
    std::vector<TransitionPlan> plans;
    int unreachable = 0;
    for (const auto& [source, target] : pairs) {
      bool reachable = false;
      TransitionPlan plan = plan_fixed(planner, fixed, source, target, reachable);
      if (reachable) plans.push_back(plan);
      else ++unreachable;
    }
    start = cpu_seconds();
    double sink = 0;
    for (int r = 0; r < options.repeats; ++r)
      for (const auto& [source, target] : pairs) {
        bool reachable = false;
        sink += plan_fixed(planner, fixed, source, target, reachable).similarity;
      }
    const double online = (cpu_seconds() - start) /
                          std::max(1.0, static_cast<double>(options.repeats) * pairs.size());
    summarise(std::to_string(count) + " precomputed" + (sink < 0 ? " " : ""), plans, online, offline, unreachable);
  }
  return {{"from", from}, {"to", to}, {"transitions", options.transitions}, {"seed", options.seed},
          {"latency_weight", planner_options.latency_weight}, {"parameter_step", planner_options.parameter_step},
          {"similarity_scale", planner_options.similarity_scale}, {"fps", planner_options.fps}, {"methods", rows}};
}

}  // namespace surfcap::runtime
