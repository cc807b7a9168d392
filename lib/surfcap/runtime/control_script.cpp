#include "surfcap/runtime/control_script.hpp"

#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::runtime {
namespace {

ControlTarget parse_target(const core::Json& json, const std::filesystem::path& file, const asset::Character& character,
                           const std::string& where) {
  ControlTarget target;
  const std::string name = core::get_field<std::string>(json, "space", file);
  target.space = character.space_index(name);
  if (target.space < 0) throw core::bad_input(file, where + ": unknown space '" + name + "'");
  const asset::CharacterSpace& space = character.spaces[target.space];
  target.parameters.assign(static_cast<std::size_t>(space.dimensions), std::nullopt);
  const core::Json parameters = json.value("parameters", core::Json::object());
  if (!parameters.is_object()) throw core::bad_input(file, where + ": \"parameters\" must be an object");
  for (const auto& [key, value] : parameters.items()) {
    const auto it = std::find(space.parameter_names.begin(), space.parameter_names.end(), key);
    if (it == space.parameter_names.end())
      throw core::bad_input(file, where + ": space '" + name + "' has no parameter '" + key + "'");
    if (!value.is_number() || !(std::abs(value.get<double>()) <= core::kMaxCoordinate))
      throw core::bad_input(file, where + ": parameter '" + key + "' must be a finite number of magnitude ≤ 1e5");
    target.parameters[static_cast<std::size_t>(it - space.parameter_names.begin())] = value.get<double>();
  }
  if (json.contains("t")) {
    if (!json["t"].is_number() || !(json["t"].get<double>() >= 0 && json["t"].get<double>() <= 1))
      throw core::bad_input(file, where + ": \"t\" must be a number in [0, 1]");
    target.t = json["t"].get<double>();
  }
  return target;
}

void require_transition(const asset::Character& character, int from, int to, const std::filesystem::path& file,
                        const std::string& where) {
  if (from == to) return;
  const std::string& a = character.spaces[from].name;
  const std::string& b = character.spaces[to].name;
  if (!character.find_transition(a, b))
    throw core::bad_input(file, where + ": the character has no transition " + a + " → " + b);
}

double positive(const core::Json& json, const char* key, double fallback, const std::filesystem::path& file,
                double max = core::kMaxCoordinate) {
  const double value = core::number_field(json, key, file, 0, max, fallback);
  if (!(value > 0)) throw core::bad_input(file, std::string("\"") + key + "\" must be positive");
  return value;
}

}  // namespace

ControlScript parse_control_script(const core::Json& json, const std::filesystem::path& file,
                                   const asset::Character& character) {
  ControlScript script;
  script.file = file;
  if (json.contains("fps")) script.fps = positive(json, "fps", 25, file, core::kMaxFps);
  script.duration_s = core::number_field(json, "duration_s", file, 0, core::kMaxDurationS, 0.0);
  script.start = parse_target(core::get_field<core::Json>(json, "start", file), file, character, "start");
  double previous_time = 0;
  int space = script.start.space;
  const core::Json timeline = json.value("timeline", core::Json::array());
  for (std::size_t k = 0; k < timeline.size(); ++k) {
    const std::string where = "timeline[" + std::to_string(k) + "]";
    TimelineEvent event;
    event.time_s = core::number_field(timeline[k], "time_s", file, 0, core::kMaxDurationS);
    if (!(event.time_s >= previous_time)) throw core::bad_input(file, where + ": times must not decrease");
    previous_time = event.time_s;
    event.target = parse_target(timeline[k], file, character, where);
    require_transition(character, space, event.target.space, file, where);
    space = event.target.space;
    script.timeline.push_back(std::move(event));
  }
  if (json.contains("travel")) script.travel = parse_target(json["travel"], file, character, "travel");
  const int travel = script.travel ? script.travel->space : script.start.space;
  require_transition(character, script.start.space, travel, file, "travel");
  const core::Json waypoints = json.value("waypoints", core::Json::array());
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    const std::string where = "waypoints[" + std::to_string(k) + "]";
    Waypoint waypoint;
    waypoint.x = core::number_field(waypoints[k], "x", file, -core::kMaxCoordinate, core::kMaxCoordinate);
    waypoint.z = core::number_field(waypoints[k], "z", file, -core::kMaxCoordinate, core::kMaxCoordinate);
    if (waypoints[k].contains("space")) {
      waypoint.target = parse_target(waypoints[k], file, character, where);
      require_transition(character, travel, waypoint.target->space, file, where);
      require_transition(character, waypoint.target->space, travel, file, where);
    }
    script.waypoints.push_back(std::move(waypoint));
  }
  if (script.duration_s == 0 && script.waypoints.empty())
    throw core::bad_input(file, "needs \"duration_s\" > 0 (or waypoints)");
  script.turn_rate = positive(json, "turn_rate", script.turn_rate, file);
  script.arrival_radius_m = positive(json, "arrival_radius_m", script.arrival_radius_m, file);
  script.max_duration_s = positive(json, "max_duration_s", script.max_duration_s, file, core::kMaxDurationS);
  // Every frame played is kept (positions for the animation and the contact sheet): refuse a
  // script whose frames cannot fit before playing any.
  const double fps = script.fps.value_or(character.fps);
  const double frames = std::ceil(fps * (script.duration_s > 0 ? script.duration_s : script.max_duration_s));
  core::check_memory(file, std::to_string(static_cast<long>(frames)) + " frames at " + std::to_string(fps) + " fps of " +
                               std::to_string(character.vertex_count()) + " vertices",
                     frames * static_cast<double>(character.vertex_count()) * 3 * 3 * sizeof(double));
  const core::Json planner = json.value("planner", core::Json::object());
  if (!planner.is_object()) throw core::bad_input(file, "\"planner\" must be an object");
  script.planner.depth = static_cast<int>(core::integer_field_or(planner, "depth", file, 0, 100, script.planner.depth));
  script.planner.latency_weight = core::number_field(planner, "latency_weight", file, 0, 1e6, script.planner.latency_weight);
  script.planner.parameter_step = core::number_field(planner, "parameter_step", file, 0, 1, script.planner.parameter_step);
  try {
    script.planner.validate();
  } catch (const core::Error& e) {
    throw core::bad_input(file, std::string("planner: ") + e.what());
  }
  return script;
}

ControlScript read_control_script(const std::filesystem::path& path, const asset::Character& character) {
  const core::Json document = core::read_json_document(path, "control", 1);
  return core::read_document_fields(path, [&] { return parse_control_script(document, path, character); });
}

}  // namespace surfcap::runtime
