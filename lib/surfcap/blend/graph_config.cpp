#include "surfcap/blend/graph_config.hpp"

#include "surfcap/blend/source_set.hpp"
#include "surfcap/core/error.hpp"
#include <limits>

#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::blend {

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

const SpaceConfig* GraphConfig::find(const std::string& name) const {
  for (const auto& space : spaces)
    if (space.name == name) return &space;
  return nullptr;
}

GraphConfig read_graph_config(const std::filesystem::path& path) {
  const core::Json json = core::read_json_document(path, "graph_config", 1);
  GraphConfig config;
  try {
    for (const auto& item : json.at("spaces")) {
      SpaceConfig space;
      space.source = path;
      space.name = core::name_field(item, "name", path);  // it names the space's output folder
      for (const auto& sequence : item.at("sequences")) {
        SequenceRange range;
        if (sequence.is_string()) {
          range.name = core::check_name(path, "sequences", sequence.get<std::string>());
        } else {
          range.name = core::name_field(sequence, "name", path);
          range.first = static_cast<int>(core::integer_field_or(sequence, "first", path, 0, core::kMaxFrames, 0));
          range.last = static_cast<int>(core::integer_field_or(sequence, "last", path, -1, core::kMaxFrames, -1));
        }
        space.sequences.push_back(range);
      }
      for (const auto& parameter : item.value("parameters", core::Json::array())) {
        ParameterSpec spec;
        spec.name = parameter.at("name").get<std::string>();
        spec.measure = parse_measure(parameter.at("measure").get<std::string>());
        for (const auto& vertex : parameter.value("vertices", core::Json::array()))
          spec.vertices.push_back(static_cast<int>(core::checked_integer(
              vertex, "parameter '" + spec.name + "': a vertex index", path, 0, std::numeric_limits<int>::max())));
        if (spec.measure == Measure::hand_height && spec.vertices.empty())
          throw core::bad_input(path, "parameter '" + spec.name + "': hand_height needs \"vertices\"");
        space.parameters.push_back(spec);
      }
      space.cyclic = item.value("cyclic", false);
      space.frames = static_cast<int>(core::integer_field_or(item, "frames", path, 0, core::kMaxFrames, 0));
      space.tolerance_mm = core::number_field(item, "tolerance_mm", path, 1e-6, 1e6, 5.0);
      // The parameter-map degree stored spaces accept (parameter_map_json).
      space.degree = static_cast<int>(core::integer_field_or(item, "degree", path, 0, 16, 2));
      const int d = weight_space_dimensions(static_cast<int>(space.sequences.size()));
      if (!space.parameters.empty() && static_cast<int>(space.parameters.size()) != d)
        throw core::bad_input(path, "space '" + space.name + "': " + std::to_string(space.sequences.size()) +
                                        " sequences need " + std::to_string(d) + " parameters");
      if (config.find(space.name)) throw core::bad_input(path, "space '" + space.name + "' declared twice");
      config.spaces.push_back(space);
    }
    for (const auto& item : json.value("transitions", core::Json::array()))
      config.transitions.push_back({item.at("from").get<std::string>(), item.at("to").get<std::string>()});
  } catch (const core::Json::exception& error) {
    throw core::bad_input(path, "malformed graph config: " + core::json_error_text(error));
  } catch (const core::Error& error) {
    if (error.code() == core::ExitCode::bad_arguments) throw core::bad_input(path, error.what());
    throw;
  }
  for (const auto& transition : config.transitions)
    if (!config.find(transition.from) || !config.find(transition.to))
      throw core::bad_input(path, "transition " + transition.from + " → " + transition.to + " names an unknown space");
  return config;
}

}  // namespace surfcap::blend
