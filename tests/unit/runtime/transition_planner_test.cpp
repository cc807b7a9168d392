#include "surfcap/runtime/transition_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

struct Fixture {
  asset::CharacterSpace walk = surfcap::testing::synthetic_space("walk", 8, 12, true, 1);
  asset::CharacterSpace jump = surfcap::testing::synthetic_space("jump", 8, 10, false, 2);
  asset::CharacterTransition matrix;
  std::unique_ptr<runtime::SpaceEvaluator> from, to;
  Fixture() {
    matrix.from = "walk";
    matrix.to = "jump";
    matrix.rows = 3 * 12;
    matrix.cols = 3 * 10;
    std::mt19937 random(5);
    std::uniform_real_distribution<float> uniform(0.2f, 0.9f);
    for (long k = 0; k < matrix.rows * matrix.cols; ++k) matrix.similarity.push_back(uniform(random));
    from = std::make_unique<runtime::SpaceEvaluator>(walk);
    to = std::make_unique<runtime::SpaceEvaluator>(jump);
  }
};

/// Exhaustive search over the same candidates through the public eq. 5 bound.
double brute_force(const runtime::TransitionPlanner& planner, const runtime::MotionState& source,
                   const runtime::MotionState& target) {
  const auto& o = planner.options();
  const auto side = [&](const runtime::SpaceEvaluator& space, const runtime::MotionState& state, int sign) {
    std::vector<std::tuple<int, double, double>> nodes;  // depth, frame, parameter
    double u0;
    space.weight_coordinates(state.parameters.data(), &u0);
    const double step = space.frames_per_step(&u0, o.fps);
    for (int k = 0; k <= o.depth; ++k) {
      const double f = state.frame + sign * k * step;
      if (!space.cyclic() && (f < 0 || f > space.frames() - 1)) break;
      for (int j = -k; j <= k; ++j) {
        const double p = std::clamp(state.parameters[0] + j * o.parameter_step, 0.0, 1.0);
        nodes.emplace_back(k, space.wrap(f), p);
      }
    }
    return nodes;
  };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [ka, fa, pa] : side(planner.from(), source, 1))
    for (const auto& [kb, fb, pb] : side(planner.to(), target, -1)) {
      double ua, ub;
      planner.from().weight_coordinates(&pa, &ua);
      planner.to().weight_coordinates(&pb, &ub);
      const double s = planner.similarity_bound(fa, &ua, fb, &ub);
      best = std::min(best, o.similarity_scale * (1 - s) + o.latency_weight * (ka + kb));
    }
  return best;
}

TEST(TransitionPlanner, FindsTheExhaustiveMinimumOfEq4) {
  Fixture f;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (double lambda : {0.0, 5.0, 40.0}) {
    runtime::PlannerOptions options;
    options.depth = 6;
    options.latency_weight = lambda;
    const runtime::TransitionPlanner planner(*f.from, *f.to, f.matrix, options);
    for (int trial = 0; trial < 20; ++trial) {
      const runtime::MotionState source{0, uniform(random) * 12, {uniform(random)}};
      const runtime::MotionState target{1, uniform(random) * 9, {uniform(random)}};
      const runtime::TransitionPlan plan = planner.plan(source, target);
      EXPECT_NEAR(plan.cost(), brute_force(planner, source, target), 1e-6) << "λ " << lambda << " trial " << trial;
      // The path: source levels forward in time, then target levels ending exactly at the target.
      ASSERT_EQ(static_cast<int>(plan.frames.size()), plan.source_steps + plan.target_steps + 1);
      EXPECT_EQ(plan.frames.back().space, 1);
      EXPECT_NEAR(plan.frames.back().frame, target.frame, 1e-9);
      EXPECT_NEAR(plan.frames.back().parameters[0], target.parameters[0], 1e-12);
      for (int k = 0; k < plan.source_steps; ++k) EXPECT_EQ(plan.frames[k].space, 0);
      for (std::size_t k = 1; k < plan.frames.size(); ++k)  // parameters change by ≤ Δp per frame within a space
        if (plan.frames[k].space == plan.frames[k - 1].space)
          EXPECT_LE(std::abs(plan.frames[k].parameters[0] - plan.frames[k - 1].parameters[0]), 0.1 + 1e-9);
    }
  }
}

TEST(TransitionPlanner, LatencyWeightTradesSimilarityForLatency) {
  Fixture f;
  runtime::PlannerOptions cheap, dear;
  cheap.latency_weight = 0.0;
  dear.latency_weight = 1e6;
  const runtime::TransitionPlanner a(*f.from, *f.to, f.matrix, cheap), b(*f.from, *f.to, f.matrix, dear);
  const runtime::MotionState source{0, 2.0, {0.3}}, target{1, 8.0, {0.6}};
  const runtime::TransitionPlan slow = a.plan(source, target), fast = b.plan(source, target);
  EXPECT_EQ(fast.source_steps + fast.target_steps, 0);  // jumps straight to the target
  EXPECT_GE(slow.similarity, fast.similarity);
  EXPECT_GT(slow.source_steps + slow.target_steps, 0);
}

TEST(TransitionPlanner, OneShotTargetsAreNotEnteredBeforeTheirStart) {
  Fixture f;
  runtime::PlannerOptions options;
  options.latency_weight = 0;
  const runtime::TransitionPlanner planner(*f.from, *f.to, f.matrix, options);
  const runtime::TransitionPlan plan = planner.plan({0, 0.0, {0.5}}, {1, 2.0, {0.5}});
  EXPECT_LE(plan.target_steps, 2);  // the backward trellis stops at frame 0 of the jump
  for (const auto& state : plan.frames)
    if (state.space == 1) EXPECT_GE(state.frame, 0.0);
}

}  // namespace
