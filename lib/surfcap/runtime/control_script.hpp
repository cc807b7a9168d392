#pragma once
// Control scripts of surfcap-play (docs/runtime.md, "surfcap.control/1"): a timeline of space +
// parameter targets over time, and/or waypoints on the ground the character walks to (casas2013
// Fig. 8c). Parsed against a character so unknown spaces and parameters are bad input.
#include <filesystem>
#include <optional>
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/runtime/transition_planner.hpp"

namespace surfcap::runtime {

/// A requested state: a space, its parameters (unnamed ones keep their current value, or the
/// middle of the range on entering the space) and optionally the normalised time t ∈ [0, 1] of
/// the target state (default: chosen by the controller, docs/runtime.md).
struct ControlTarget {
  int space = 0;
  std::vector<std::optional<double>> parameters;  ///< one per space dimension
  std::optional<double> t;
};

struct TimelineEvent {
  double time_s = 0;
  ControlTarget target;
};

struct Waypoint {
  double x = 0, z = 0;                 ///< ground-plane position (metres)
  std::optional<ControlTarget> target;  ///< state requested on arrival (e.g. a jump), if any
};

struct ControlScript {
  std::filesystem::path file;
  std::optional<double> fps;  ///< output frame rate; default the character's
  double duration_s = 0;      ///< frames = duration·fps; with waypoints 0 means "until the last is reached"
  ControlTarget start;
  std::vector<TimelineEvent> timeline;  ///< sorted by time
  std::vector<Waypoint> waypoints;
  std::optional<ControlTarget> travel;  ///< the state to walk in between waypoints; default `start`
  double turn_rate = 1.5;               ///< rad/s of steering towards a waypoint
  double arrival_radius_m = 0.3;
  double max_duration_s = 120;          ///< bound on waypoint scripts
  PlannerOptions planner;
};

/// Reads and checks a control script: spaces and parameter names must exist in `character`,
/// every change of space along the timeline must be a transition of the character, times must
/// rise; bad_input (exit 3) naming the file otherwise.
ControlScript read_control_script(const std::filesystem::path& path, const asset::Character& character);

/// Same from parsed JSON (tests); `file` names it in errors.
ControlScript parse_control_script(const core::Json& json, const std::filesystem::path& file,
                                   const asset::Character& character);

}  // namespace surfcap::runtime
