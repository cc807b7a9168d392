#pragma once
// A Character with every field filled (two sequences, a 1-D space with a parameter map, a 2-D
// space, a transition, two parts with regions, colours, UVs and a texture), every array holding
// float32-representable values as assembled characters do; shared by the asset tests and the
// asset benchmarks.
#include <cmath>
#include <random>

#include "surfcap/asset/character.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::testing {

struct SyntheticCharacterShape {
  int frames = 6;           ///< per sequence and per space (T)
  int extra_nodes = 1;      ///< bisection nodes beyond the corners of the 1-D space
  double stored_share = 0.2;  ///< share of vertices with a stored displacement at a non-corner node
};

inline asset::Character synthetic_character(const core::Mesh& mesh, const SyntheticCharacterShape& shape = {},
                                            unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const long v = mesh.vertex_count();
  asset::Character c;
  c.name = "synthetic";
  c.fps = 25;
  c.template_mesh = mesh;
  c.template_mesh.V = mesh.V.cast<float>().cast<double>();
  c.template_mesh.colors.resize(v, 3);
  c.template_mesh.uvs.resize(v, 2);
  for (long i = 0; i < v; ++i) {
    for (int k = 0; k < 3; ++k) c.template_mesh.colors(i, k) = static_cast<int>(unit(rng) * 255) / 255.0;
    c.template_mesh.uvs.row(i) << unit(rng), unit(rng);
  }
  for (const char* name : {"walk", "run"}) {
    core::AlignedSequence s;
    s.name = name;
    for (int t = 0; t < shape.frames; ++t) {
      Eigen::MatrixXd frame = c.template_mesh.V;
      for (long i = 0; i < frame.size(); ++i) frame.data()[i] = static_cast<float>(frame.data()[i] + noise(rng));
      s.frames.push_back(frame);
      s.root_motion.push_back({0.1f * t, 0.9f, -0.05f * t, static_cast<float>(0.3 * t)});
    }
    c.sequences.push_back(s);
  }
  auto random_floats = [&](std::size_t n) {
    std::vector<float> values(n);
    for (auto& x : values) x = noise(rng);
    return values;
  };
  for (int d : {1, 2}) {
    asset::CharacterSpace s;
    s.name = d == 1 ? "locomotion" : "turns";
    s.cyclic = d == 1;
    s.frames = shape.frames;
    s.dimensions = d;
    for (int i = 0; i < s.source_count(); ++i)
      s.sources.push_back({c.sequences[i % 2].name, i, shape.frames, (shape.frames - 1) / 25.0});
    if (d == 1) {
      s.parameter_names = {"speed"};
      s.parameter_measures = {"root_speed"};
      s.breakpoints = {{0, 1}};
      s.node_coordinates = {{0}, {1}};
      for (int k = 1; k <= shape.extra_nodes; ++k) {
        s.node_coordinates.push_back({k / (shape.extra_nodes + 1.0)});
        s.breakpoints[0].insert(s.breakpoints[0].end() - 1, k / (shape.extra_nodes + 1.0));
      }
      blend::ParameterMap map;
      map.parameters = {"speed"};
      map.monomials = {{0}, {1}, {2}};
      map.coefficients = Eigen::MatrixXd(1, 3);
      map.coefficients << -0.25, 0.7 / 3, 1e-3 / 7;
      map.parameter_range = Eigen::MatrixXd(1, 2);
      map.parameter_range << 1.1, 3.3;
      map.residual_rms = 0.01 / 3;
      map.residual_max = 0.02;
      s.parameter_map = map;
    } else {
      s.breakpoints = {{0, 1}, {0, 1}};
      s.node_coordinates = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    }
    const std::size_t n = s.source_count(), t = s.frames;
    s.references = random_floats(n * t * v * 3);
    s.root_motion = random_floats(n * t * 4);
    s.time_warp = random_floats(n * t);
    s.displacement_offsets.push_back(0);
    for (long node = 0; node < s.node_count(); ++node)
      for (std::size_t f = 0; f < t; ++f) {
        if (node >= s.source_count())
          for (long i = 0; i < v; ++i)
            if (unit(rng) < shape.stored_share) {
              s.displacement_vertices.push_back(static_cast<std::int32_t>(i));
              for (int k = 0; k < 3; ++k) s.displacement_values.push_back(core::float_to_half(noise(rng)));
            }
        s.displacement_offsets.push_back(static_cast<std::int64_t>(s.displacement_vertices.size()));
      }
    s.displacement_threshold_m = 0.0005;
    s.tolerance_mm = 5;
    s.max_error_mm = 4.25;
    c.spaces.push_back(s);
  }
  asset::CharacterTransition transition{"locomotion", "turns", c.spaces[0].node_count() * shape.frames,
                                        c.spaces[1].node_count() * shape.frames, {}};
  for (long i = 0; i < transition.rows * transition.cols; ++i) transition.similarity.push_back(unit(rng));
  c.transitions.push_back(transition);
  learn::LearntModel parts;
  parts.template_mesh = c.template_mesh;
  for (int p = 0; p < 2; ++p) {
    learn::PartModel part;
    part.part.name = p == 0 ? "torso" : "arm";
    part.part.parent = p - 1;
    for (long i = p == 0 ? 0 : v / 2; i < (p == 0 ? v / 2 + 3 : v); ++i) part.part.vertices.push_back(static_cast<int>(i));
    if (p == 1) part.part.frontier = {static_cast<int>(v / 2), static_cast<int>(v / 2) + 1, static_cast<int>(v / 2) + 2};
    const long values = 3 * static_cast<long>(part.part.vertices.size());
    part.mean = Eigen::VectorXd(values);
    part.basis = Eigen::MatrixXd(values, 2 + p);
    for (long i = 0; i < part.mean.size(); ++i) part.mean(i) = noise(rng);
    for (long i = 0; i < part.basis.size(); ++i) part.basis.data()[i] = noise(rng);
    part.singular_values = Eigen::Vector3d(3.0, 2.0 / 3, 1.0 / 7);
    part.energy = 0.95 + 1e-9;
    parts.parts.push_back(part);
  }
  parts.regions["hand_l"] = {static_cast<int>(v - 1), static_cast<int>(v - 2)};
  parts.examples = {{"walk", 0}, {"run", 3}};
  c.parts = parts;
  c.provenance = {{"tool", "test"}, {"empty", core::Json::array()}, {"nothing", nullptr}, {"big", 1LL << 40}};
  return c;
}

}  // namespace surfcap::testing
