#pragma once
// One motion space as a graph config declares it (configs/graphs/*.json "spaces", docs/blend.md):
// its sequences, its high-level parameters and how each is measured.
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"

namespace surfcap::blend {

/// Measures of a blended motion (computed from the blended meshes and root motion).
enum class Measure { root_speed, turning_rate, jump_height, jump_length, hand_height };
Measure parse_measure(const std::string& name);  ///< bad_arguments for unknown names
std::string measure_name(Measure measure);

struct ParameterSpec {
  std::string name;
  Measure measure = Measure::root_speed;
  std::vector<int> vertices;  ///< hand_height: the vertices whose mean height is measured
};

struct SequenceRange {
  std::string name;
  int first = 0;
  int last = -1;  ///< inclusive; −1: the last frame
};

struct SpaceConfig {
  std::string name;
  std::vector<SequenceRange> sequences;  ///< 2^d, corner order of SourceSet
  std::vector<ParameterSpec> parameters;  ///< d (one per weight-space axis), or none
  bool cyclic = false;
  int frames = 0;             ///< normalised frames; 0: the first sequence's frame count
  double tolerance_mm = 5.0;  ///< ε of the hybrid bisection
  int degree = 2;             ///< parameter map polynomial degree
  std::filesystem::path source = "graph config";  ///< the file it was read from, for messages
};

/// Parses one entry of a graph config's "spaces" read from `path`. Throws bad_input naming `path`
/// and the field, bad_arguments for an unknown measure, and core::Json::exception for a missing or
/// mistyped field; the caller (graph::read_graph_config) words the last two as bad_input.
SpaceConfig parse_space_config(const core::Json& item, const std::filesystem::path& path);

}  // namespace surfcap::blend
