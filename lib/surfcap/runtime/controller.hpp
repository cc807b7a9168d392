#pragma once
// The character controller of surfcap-play (docs/runtime.md): follows a control script frame by
// frame — parameter changes ramp at Δp per frame, a change of space is planned by the
// TransitionPlanner and played through the path's frames (each a hybrid blend at its trellis
// state), one-shot spaces return to the space they were entered from, waypoints are reached by
// steering — and evaluates the world-space mesh of every frame.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/runtime/control_script.hpp"
#include "surfcap/runtime/space_evaluator.hpp"
#include "surfcap/runtime/transition_planner.hpp"

namespace surfcap::runtime {

/// What one produced frame is.
struct FrameState {
  long index = 0;
  MotionState state;
  std::vector<double> weights;  ///< u = h⁻¹(p)
  bool in_transition = false;   ///< a frame of a planned transition path
  Eigen::Vector3d root = Eigen::Vector3d::Zero();  ///< world position of the root (x, height, z)
  double heading = 0;                              ///< radians about +y
};

struct TransitionRecord {
  long frame = 0;  ///< frame at which it was planned
  std::string from, to;
  double similarity = 0, similarity_cost = 0, latency_cost = 0;
  int frames = 0;          ///< E_L
  double latency_s = 0;    ///< E_L / fps
  double planning_s = 0;   ///< CPU time (thread) of the plan
  long evaluated_pairs = 0;
};

class Controller {
 public:
  /// `character` and `script` must outlive the controller.
  Controller(const asset::Character& character, const ControlScript& script);
  ~Controller();

  double fps() const { return fps_; }
  /// No more frames: the duration is over (or, for waypoint scripts, the last was reached).
  bool done() const;
  /// Advances one frame and evaluates it; the mesh is then in world_positions().
  const FrameState& step();
  /// V×3 floats, row-major, world coordinates of the last frame.
  const std::vector<float>& world_positions() const { return world_; }
  /// The centred mesh of the last frame (before root placement).
  const std::vector<float>& centred_positions() const { return centred_; }
  const std::vector<TransitionRecord>& transitions() const { return transitions_; }
  const SpaceEvaluator& evaluator(int space) const { return *evaluators_[space]; }
  /// Thread CPU seconds spent evaluating meshes (blend + world placement), over all frames so far.
  double evaluation_seconds() const { return evaluation_s_; }

 private:
  std::vector<double> resolve_parameters(const ControlTarget& target, const std::vector<double>* current) const;
  void request(const ControlTarget& target);
  void begin_transition(int to, const std::vector<double>& parameters, std::optional<double> t);
  void follow_waypoints();
  void advance();
  void evaluate();
  const TransitionPlanner* planner(int from, int to) const;

  const asset::Character* character_;
  const ControlScript* script_;
  double fps_ = 25;
  long total_frames_ = 0;
  std::vector<std::unique_ptr<SpaceEvaluator>> evaluators_;
  std::map<std::pair<int, int>, std::unique_ptr<TransitionPlanner>> planners_;
  FrameState current_;
  std::vector<double> parameter_target_;
  std::vector<MotionState> path_;  // remaining transition frames, next first
  std::size_t path_next_ = 0;
  std::vector<ControlTarget> pending_;  // requests that arrived during a transition
  int return_space_ = -1;               // where a one-shot space goes back to
  std::vector<double> return_parameters_;
  std::size_t next_event_ = 0, next_waypoint_ = 0;
  bool started_ = false, arrived_all_ = false;
  std::vector<float> centred_, world_;
  std::vector<TransitionRecord> transitions_;
  double evaluation_s_ = 0;
};

}  // namespace surfcap::runtime
