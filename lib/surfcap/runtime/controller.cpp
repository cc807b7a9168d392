#include "surfcap/runtime/controller.hpp"

#include <algorithm>
#include <ctime>
#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

#include "surfcap/core/error.hpp"

namespace surfcap::runtime {
namespace {

/// CPU time of the calling thread (seconds): what the runtime costs, whatever else the machine runs.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

/// Angle of a ground vector in the R_y convention (R_y(a)·(1, 0) = (cos a, −sin a)).
double ground_angle(const Eigen::Vector2d& v) { return std::atan2(-v(1), v(0)); }

}  // namespace

Controller::Controller(const asset::Character& character, const ControlScript& script)
    : character_(&character), script_(&script), fps_(script.fps.value_or(character.fps)) {
  for (const asset::CharacterSpace& space : character.spaces) evaluators_.push_back(std::make_unique<SpaceEvaluator>(space));
  PlannerOptions options = script.planner;
  options.fps = fps_;
  for (const asset::CharacterTransition& transition : character.transitions) {
    const int from = character.space_index(transition.from), to = character.space_index(transition.to);
    planners_[{from, to}] = std::make_unique<TransitionPlanner>(*evaluators_[from], *evaluators_[to], transition, options);
  }
  const double duration = script.duration_s > 0 ? script.duration_s : script.max_duration_s;
  total_frames_ = std::max<long>(1, std::lround(duration * fps_));
  const ControlTarget& start = script.start;
  const SpaceEvaluator& space = *evaluators_[start.space];
  current_.state = {start.space, space.wrap(start.t.value_or(0.0) * (space.frames() - 1)),
                    resolve_parameters(start, nullptr)};
  parameter_target_ = current_.state.parameters;
  centred_.assign(static_cast<std::size_t>(space.vertex_count() * 3), 0.0f);
  world_ = centred_;
}

Controller::~Controller() = default;

bool Controller::done() const {
  if (!started_) return false;
  if (current_.index + 1 >= total_frames_) return true;
  return script_->duration_s == 0 && arrived_all_ && path_next_ >= path_.size() &&
         evaluators_[current_.state.space]->cyclic();
}

const TransitionPlanner* Controller::planner(int from, int to) const {
  const auto it = planners_.find({from, to});
  return it == planners_.end() ? nullptr : it->second.get();
}

std::vector<double> Controller::resolve_parameters(const ControlTarget& target, const std::vector<double>* current) const {
  const SpaceEvaluator& space = *evaluators_[target.space];
  std::vector<double> values(static_cast<std::size_t>(space.dimensions()));
  for (int a = 0; a < space.dimensions(); ++a) {
    const double low = space.parameter_min(a), high = space.parameter_max(a);
    if (target.parameters[a]) values[a] = std::clamp(*target.parameters[a], low, high);
    else if (current) values[a] = (*current)[a];
    else values[a] = 0.5 * (low + high);
  }
  return values;
}

void Controller::request(const ControlTarget& target) {
  if (path_next_ < path_.size()) {
    pending_.push_back(target);
    return;
  }
  const bool same = target.space == current_.state.space;
  const std::vector<double> parameters = resolve_parameters(target, same ? &current_.state.parameters : nullptr);
  if (same) {
    parameter_target_ = parameters;
    return;
  }
  if (evaluators_[target.space]->cyclic()) {
    return_space_ = -1;
  } else if (evaluators_[current_.state.space]->cyclic()) {
    return_space_ = current_.state.space;
    return_parameters_ = current_.state.parameters;
  }
  begin_transition(target.space, parameters, target.t);
}

void Controller::begin_transition(int to, const std::vector<double>& parameters, std::optional<double> t) {
  const TransitionPlanner* planner = this->planner(current_.state.space, to);
  if (!planner) {
    spdlog::warn("{}: no transition {} → {}; staying", script_->file.string(), character_->spaces[current_.state.space].name,
                 character_->spaces[to].name);
    return;
  }
  const SpaceEvaluator& target_space = *evaluators_[to];
  std::vector<double> candidates;
  if (t) {
    candidates.push_back(*t * (target_space.frames() - 1));
  } else if (target_space.cyclic()) {
    for (int k = 0; k < 8; ++k) candidates.push_back(k * target_space.frames() / 8.0);
  } else {
    std::vector<double> u(parameters.size());
    target_space.weight_coordinates(parameters.data(), u.data());
    const double step = target_space.frames_per_step(u.data(), fps_);
    candidates.push_back(std::min<double>(target_space.frames() - 1, planner->options().depth * step));
  }
  const double start = thread_cpu_seconds();
  TransitionPlan best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (double frame : candidates) {
    TransitionPlan plan = planner->plan(current_.state, MotionState{to, frame, parameters});
    if (plan.cost() < best_cost) {
      best_cost = plan.cost();
      best = std::move(plan);
    }
  }
  TransitionRecord record;
  record.planning_s = thread_cpu_seconds() - start;
  record.frame = current_.index;
  record.from = character_->spaces[current_.state.space].name;
  record.to = target_space.space().name;
  record.similarity = best.similarity;
  record.similarity_cost = best.similarity_cost;
  record.latency_cost = best.latency_cost;
  record.frames = best.source_steps + best.target_steps;
  record.latency_s = record.frames / fps_;
  record.evaluated_pairs = best.evaluated_pairs;
  transitions_.push_back(record);
  path_ = std::move(best.frames);
  path_next_ = 0;
  parameter_target_ = parameters;
}

void Controller::follow_waypoints() {
  if (script_->waypoints.empty()) return;
  if (next_waypoint_ >= script_->waypoints.size()) {
    arrived_all_ = true;
    return;
  }
  const SpaceEvaluator& space = *evaluators_[current_.state.space];
  if (!space.cyclic() || path_next_ < path_.size()) return;
  const Waypoint& waypoint = script_->waypoints[next_waypoint_];
  const Eigen::Vector2d to(waypoint.x - current_.root(0), waypoint.z - current_.root(2));
  if (to.norm() < script_->arrival_radius_m) {
    ++next_waypoint_;
    if (waypoint.target) request(*waypoint.target);
    return;
  }
  // Steer: turn the heading towards the waypoint at no more than turn_rate.
  double u[3];
  space.weight_coordinates(current_.state.parameters.data(), u);
  const double frame = current_.state.frame;
  const Eigen::Vector3d ahead = space.root_step(frame, frame + space.frames() / 2.0, u);
  if (ahead.head<2>().norm() < 1e-6) return;
  const Eigen::Vector2d heading = rotate_ground(ahead.head<2>(), current_.heading);
  const double error = std::remainder(ground_angle(to) - ground_angle(heading), 2 * M_PI);
  const double limit = script_->turn_rate / fps_;
  current_.heading += std::clamp(error, -limit, limit);
}

void Controller::advance() {
  MotionState next = current_.state;
  const SpaceEvaluator* space = evaluators_[next.space].get();
  double u[3];
  Eigen::Vector3d delta;
  if (path_next_ < path_.size()) {
    next = path_[path_next_++];
    space = evaluators_[next.space].get();
    space->weight_coordinates(next.parameters.data(), u);
    double previous = current_.state.frame;
    if (next.space != current_.state.space) {
      // The switch itself moves the root as the target space moves into its first path frame.
      previous = next.frame - space->frames_per_step(u, fps_);
      if (!space->cyclic()) previous = std::max(0.0, previous);
    }
    delta = space->root_step(previous, next.frame, u);
    current_.in_transition = true;
    parameter_target_ = next.parameters;
  } else {
    current_.in_transition = false;
    for (std::size_t a = 0; a < next.parameters.size(); ++a) {
      const double limit = script_->planner.parameter_step * (space->parameter_max(static_cast<int>(a)) -
                                                              space->parameter_min(static_cast<int>(a)));
      next.parameters[a] += std::clamp(parameter_target_[a] - next.parameters[a], -limit, limit);
    }
    space->weight_coordinates(next.parameters.data(), u);
    double frame = next.frame + space->frames_per_step(u, fps_);
    if (!space->cyclic()) frame = std::min(frame, space->frames() - 1.0);
    delta = space->root_step(next.frame, frame, u);
    next.frame = space->wrap(frame);
  }
  const Eigen::Vector2d moved = rotate_ground(delta.head<2>(), current_.heading);
  current_.root(0) += moved(0);
  current_.root(2) += moved(1);
  current_.heading += delta(2);
  current_.state = next;
  if (path_next_ >= path_.size() && !path_.empty()) {
    path_.clear();
    path_next_ = 0;
    std::vector<ControlTarget> pending;
    pending.swap(pending_);
    for (const ControlTarget& target : pending) request(target);
  }
  // A one-shot space returns where it was entered from, planned while the trellis still fits.
  if (path_.empty() && !space->cyclic() && return_space_ >= 0) {
    const double step = space->frames_per_step(u, fps_);
    if (next.frame + script_->planner.depth * step >= space->frames() - 1 - 1e-9) {
      const int back = return_space_;
      return_space_ = -1;
      begin_transition(back, return_parameters_, std::nullopt);
    }
  }
}

void Controller::evaluate() {
  const double start = thread_cpu_seconds();
  const SpaceEvaluator& space = *evaluators_[current_.state.space];
  current_.weights.resize(static_cast<std::size_t>(space.dimensions()));
  space.weight_coordinates(current_.state.parameters.data(), current_.weights.data());
  space.evaluate(current_.state.frame, current_.weights.data(), centred_.data());
  current_.root(1) = space.root_height(current_.state.frame, current_.weights.data());
  const float c = static_cast<float>(std::cos(current_.heading)), s = static_cast<float>(std::sin(current_.heading));
  const auto x = static_cast<float>(current_.root(0)), y = static_cast<float>(current_.root(1)),
             z = static_cast<float>(current_.root(2));
  const std::size_t n = centred_.size() / 3;
  for (std::size_t v = 0; v < n; ++v) {
    const float* p = centred_.data() + v * 3;
    float* out = world_.data() + v * 3;
    // world = R_y(heading)·centred + root (core::to_world).
    out[0] = c * p[0] + s * p[2] + x;
    out[1] = p[1] + y;
    out[2] = -s * p[0] + c * p[2] + z;
  }
  evaluation_s_ += thread_cpu_seconds() - start;
}

const FrameState& Controller::step() {
  if (!started_) {
    started_ = true;
    if (script_->travel) request(*script_->travel);
    evaluate();
    return current_;
  }
  ++current_.index;
  const double time = current_.index / fps_;
  while (next_event_ < script_->timeline.size() && script_->timeline[next_event_].time_s <= time + 1e-9)
    request(script_->timeline[next_event_++].target);
  follow_waypoints();
  advance();
  evaluate();
  return current_;
}

}  // namespace surfcap::runtime
