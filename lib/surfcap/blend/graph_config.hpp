#pragma once
// The graph config (configs/graphs/*.json, docs/blend.md): motion spaces, their high-level
// parameters and how each is measured, and the allowed transitions.
#include <filesystem>
#include <string>
#include <vector>

namespace surfcap::blend {

/// Measures of a blended motion (computed from the blended meshes and root motion).
enum class Measure { root_speed, turning_rate, jump_height, jump_length, hand_height };
Measure parse_measure(const std::string& name);  ///< bad_input for unknown names
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

struct TransitionConfig {
  std::string from, to;
};

struct GraphConfig {
  std::vector<SpaceConfig> spaces;
  std::vector<TransitionConfig> transitions;
  const SpaceConfig* find(const std::string& name) const;
};

/// Reads {"format": "surfcap.graph_config/1", ...}; bad_input names the file and field.
GraphConfig read_graph_config(const std::filesystem::path& path);

}  // namespace surfcap::blend
