// Runtime benchmarks (docs/runtime.md): planning one transition at trellis depth 10 (target
// ≤ 20 µs) and playing a 3,027-vertex character (target ≥ 2,000 frames/s on one core).
// With SURFCAP_BENCH_DATABASE and SURFCAP_BENCH_GRAPH set (database.json and graph.json of a
// build, e.g. the synth demo), the real character is used; otherwise an in-memory character of
// the synth demo's sizes (3,027 vertices, 9 grid nodes per space, T = 28 and 40, float16 fields
// on every vertex, similarities uniform in [0.8, 1]).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <random>

#include "surfcap/asset/character.hpp"
#include "surfcap/runtime/controller.hpp"
#include "surfcap/runtime/transition_planner.hpp"
#include "synthetic_space.hpp"

namespace {

using namespace surfcap;

asset::Character synthetic_character() {
  asset::Character character;
  character.name = "bench";
  character.fps = 25;
  constexpr long V = 3027;
  character.template_mesh.V = Eigen::MatrixXd::Zero(V, 3);
  character.spaces.push_back(surfcap::testing::synthetic_space("locomotion", V, 28, true, 1, 0.05, 0.11, 9, 1.0));
  character.spaces.push_back(surfcap::testing::synthetic_space("jump", V, 40, false, 2, 0.0, 0.02, 9, 1.0));
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0.8f, 1.0f);
  for (auto [from, to] : {std::pair{0, 1}, std::pair{1, 0}}) {
    asset::CharacterTransition transition;
    transition.from = character.spaces[from].name;
    transition.to = character.spaces[to].name;
    transition.rows = 9L * character.spaces[from].frames;
    transition.cols = 9L * character.spaces[to].frames;
    for (long k = 0; k < transition.rows * transition.cols; ++k) transition.similarity.push_back(uniform(random));
    character.transitions.push_back(std::move(transition));
  }
  return character;
}

const asset::Character& character() {
  static const asset::Character instance = [] {
    const char* database = std::getenv("SURFCAP_BENCH_DATABASE");
    const char* graph = std::getenv("SURFCAP_BENCH_GRAPH");
    if (database && graph) return asset::assemble_character({database, graph, "", "bench"});
    return synthetic_character();
  }();
  return instance;
}

runtime::MotionState random_state(const runtime::SpaceEvaluator& space, int index, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  return {index, uniform(random) * (space.frames() - 1),
          {space.parameter_min(0) + uniform(random) * (space.parameter_max(0) - space.parameter_min(0))}};
}

void BM_PlanTransition(benchmark::State& state) {
  const asset::Character& c = character();
  const runtime::SpaceEvaluator from(c.spaces[0]), to(c.spaces[1]);
  runtime::PlannerOptions options;
  options.depth = static_cast<int>(state.range(0));
  const runtime::TransitionPlanner planner(from, to, c.transitions[0], options);
  std::mt19937 random(2013);
  std::vector<std::pair<runtime::MotionState, runtime::MotionState>> pairs;
  for (int k = 0; k < 64; ++k) {
    runtime::MotionState source = random_state(from, 0, random);
    runtime::MotionState target = random_state(to, 1, random);
    pairs.emplace_back(std::move(source), std::move(target));
  }
  std::size_t k = 0;
  long pairs_evaluated = 0;
  for (auto _ : state) {
    const auto& [source, target] = pairs[k++ % pairs.size()];
    const runtime::TransitionPlan plan = planner.plan(source, target);
    pairs_evaluated += plan.evaluated_pairs;
    benchmark::DoNotOptimize(plan.similarity);
  }
  state.counters["pairs"] = benchmark::Counter(static_cast<double>(pairs_evaluated) / state.iterations());
}
BENCHMARK(BM_PlanTransition)->Arg(10)->Arg(12)->Unit(benchmark::kMicrosecond);

void BM_PlayFrame(benchmark::State& state) {
  const asset::Character& c = character();
  const auto& speed = c.spaces[0].parameter_names;
  core::Json timeline = core::Json::array();
  for (int k = 1; k < 2000; ++k)
    timeline.push_back({{"time_s", 2.0 * k}, {"space", "locomotion"},
                        {"parameters", {{speed[0], k % 2 ? c.spaces[0].parameter_map->parameter_range(0, 1)
                                                         : c.spaces[0].parameter_map->parameter_range(0, 0)}}}});
  const core::Json json = {{"duration_s", 4000}, {"start", {{"space", "locomotion"}}}, {"timeline", timeline}};
  const runtime::ControlScript script = runtime::parse_control_script(json, "bench.json", c);
  runtime::Controller controller(c, script);
  for (auto _ : state) {
    controller.step();
    benchmark::DoNotOptimize(controller.world_positions().data());
  }
  state.counters["vertices"] = static_cast<double>(c.vertex_count());
  state.counters["frames/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PlayFrame)->Unit(benchmark::kMicrosecond);

}  // namespace
