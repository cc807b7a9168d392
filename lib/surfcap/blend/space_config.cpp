#include "surfcap/blend/space_config.hpp"

#include <limits>

#include "surfcap/blend/source_set.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::blend {
namespace {

SequenceRange parse_sequence_range(const core::Json& sequence, const std::filesystem::path& path) {
  SequenceRange range;
  if (sequence.is_string()) {
    range.name = core::check_name(path, "sequences", sequence.get<std::string>());
  } else {
    range.name = core::name_field(sequence, "name", path);
    range.first = static_cast<int>(core::integer_field_or(sequence, "first", path, 0, core::kMaxFrames, 0));
    range.last = static_cast<int>(core::integer_field_or(sequence, "last", path, -1, core::kMaxFrames, -1));
  }
  return range;
}

ParameterSpec parse_parameter_spec(const core::Json& parameter, const std::filesystem::path& path) {
  ParameterSpec spec;
  spec.name = parameter.at("name").get<std::string>();
  spec.measure = parse_measure(parameter.at("measure").get<std::string>());
  for (const auto& vertex : parameter.value("vertices", core::Json::array()))
    spec.vertices.push_back(static_cast<int>(core::checked_integer(
        vertex, "parameter '" + spec.name + "': a vertex index", path, 0, std::numeric_limits<int>::max())));
  if (spec.measure == Measure::hand_height && spec.vertices.empty())
    throw core::bad_input(path, "parameter '" + spec.name + "': hand_height needs \"vertices\"");
  return spec;
}

}  // namespace

Measure parse_measure(const std::string& name) {
  for (Measure m : {Measure::root_speed, Measure::turning_rate, Measure::jump_height, Measure::jump_length,
                    Measure::hand_height})
    if (measure_name(m) == name) return m;
  throw core::bad_arguments("unknown measure '" + name +
                            "' (root_speed, turning_rate, jump_height, jump_length, hand_height)");
}

std::string measure_name(Measure measure) {
  switch (measure) {
    case Measure::root_speed: return "root_speed";
    case Measure::turning_rate: return "turning_rate";
    case Measure::jump_height: return "jump_height";
    case Measure::jump_length: return "jump_length";
    case Measure::hand_height: return "hand_height";
  }
  return "?";
}

SpaceConfig parse_space_config(const core::Json& item, const std::filesystem::path& path) {
  SpaceConfig space;
  space.source = path;
  space.name = core::name_field(item, "name", path);  // it names the space's output folder
  for (const auto& sequence : item.at("sequences")) space.sequences.push_back(parse_sequence_range(sequence, path));
  for (const auto& parameter : item.value("parameters", core::Json::array()))
    space.parameters.push_back(parse_parameter_spec(parameter, path));
  space.cyclic = item.value("cyclic", false);
  space.frames = static_cast<int>(core::integer_field_or(item, "frames", path, 0, core::kMaxFrames, 0));
  space.tolerance_mm = core::number_field(item, "tolerance_mm", path, 1e-6, 1e6, 5.0);
  // The parameter-map degree stored spaces accept (parameter_map_json).
  space.degree = static_cast<int>(core::integer_field_or(item, "degree", path, 0, 16, 2));
  const int d = weight_space_dimensions(static_cast<int>(space.sequences.size()));
  if (!space.parameters.empty() && static_cast<int>(space.parameters.size()) != d)
    throw core::bad_input(path, "space '" + space.name + "': " + std::to_string(space.sequences.size()) +
                                    " sequences need " + std::to_string(d) + " parameters");
  return space;
}

}  // namespace surfcap::blend
