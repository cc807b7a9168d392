#pragma once
// A motion space built in memory (no pipeline run): 2 sources of V vertices and T frames,
// `nodes` grid nodes evenly spaced in [0, 1] (default {0, 0.5, 1}), displacement fields on
// `displaced_fraction` of the vertices at every inner node, root motion walking along +x at a
// source-dependent speed. For graph and runtime unit tests and the runtime benchmarks.
#include <cmath>
#include <random>
#include <string>

#include "surfcap/asset/character.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::testing {

inline asset::CharacterSpace synthetic_space(const std::string& name, long V, int T, bool cyclic, unsigned seed,
                                             double speed0 = 0.04, double speed1 = 0.08, int nodes = 3,
                                             double displaced_fraction = 0.5) {
  asset::CharacterSpace space;
  space.name = name;
  space.cyclic = cyclic;
  space.frames = T;
  space.dimensions = 1;
  space.sources = {{name + "_a", 0, T, (T - 1) / 25.0}, {name + "_b", 0, T, (T - 1) / 25.0}};
  space.parameter_names = {"u"};
  space.parameter_measures = {"root_speed"};
  space.breakpoints.assign(1, {});
  for (int node = 0; node < nodes; ++node) {
    space.breakpoints[0].push_back(static_cast<double>(node) / (nodes - 1));
    space.node_coordinates.push_back({space.breakpoints[0].back()});
  }
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<double> base(static_cast<std::size_t>(V * 3));
  for (double& value : base) value = noise(random) * 10;
  space.references.resize(static_cast<std::size_t>(2 * T * V * 3));
  space.root_motion.resize(static_cast<std::size_t>(2 * T * 4));
  space.time_warp.resize(static_cast<std::size_t>(2 * T));
  for (int i = 0; i < 2; ++i)
    for (int t = 0; t < T; ++t) {
      const double phase = 2 * M_PI * t / T;
      for (long v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c)
          space.references[((static_cast<std::size_t>(i) * T + t) * V + v) * 3 + c] =
              static_cast<float>(base[v * 3 + c] + (0.05 + 0.1 * i) * std::sin(phase + v * 0.3 + c));
      float* root = space.root_motion.data() + (static_cast<std::size_t>(i) * T + t) * 4;
      root[0] = static_cast<float>((i ? speed1 : speed0) * t);
      root[1] = static_cast<float>(0.9 + 0.02 * std::sin(phase));
      root[2] = 0;
      root[3] = 0;
      space.time_warp[static_cast<std::size_t>(i) * T + t] = static_cast<float>(t);
    }
  // Inner nodes: a displacement of the first V·fraction vertices at every frame.
  space.displacement_offsets.push_back(0);
  const auto displaced = static_cast<long>(V * displaced_fraction);
  for (int node = 0; node < nodes; ++node)
    for (int t = 0; t < T; ++t) {
      if (node > 0 && node + 1 < nodes)
        for (long v = 0; v < displaced; ++v) {
          space.displacement_vertices.push_back(static_cast<std::int32_t>(v));
          for (int c = 0; c < 3; ++c)
            space.displacement_values.push_back(core::float_to_half(static_cast<float>(0.01 * (c + 1) * std::cos(t + v))));
        }
      space.displacement_offsets.push_back(static_cast<std::int64_t>(space.displacement_vertices.size()));
    }
  blend::ParameterMap map;
  map.degree = 1;
  map.parameters = {"u"};
  map.monomials = {{0}, {1}};
  map.coefficients = Eigen::MatrixXd(1, 2);
  map.coefficients << 0.0, 1.0;  // u = p
  map.parameter_range = Eigen::MatrixXd(1, 2);
  map.parameter_range << 0.0, 1.0;
  space.parameter_map = map;
  space.tolerance_mm = 5;
  return space;
}

}  // namespace surfcap::testing
