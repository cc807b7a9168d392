#include "surfcap/synth/motion.hpp"

#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"

namespace surfcap::synth {
namespace {

constexpr double degrees = M_PI / 180.0;
constexpr double gravity = 9.81;

double lerp(double a, double b, double s) { return a + (b - a) * s; }
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}
Eigen::Matrix3d rot_x(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d rot_z(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
/// Sagittal flexion of a leg joint: > 0 swings the bone below it forward.
Eigen::Matrix3d leg_flex(double a) { return rot_x(-a); }

/// Gait style as a function of speed: 0 = walk (1.3 m/s) … 1 = run (3 m/s).
double run_amount(double speed) { return std::clamp((speed - 1.3) / (3.0 - 1.3), 0.0, 1.0); }

/// The arm hangs `lower` below the A-pose and swings forward by `swing`; side +1 left, −1 right.
void set_arm(Pose& pose, const Skeleton& sk, int side, double lower, double swing, double elbow) {
  const int shoulder = side > 0 ? shoulder_l : shoulder_r;
  pose.local[shoulder] = rot_z(-side * lower) * flex(sk, shoulder, swing);
  pose.local[shoulder + 1] = flex(sk, shoulder + 1, elbow);
}

void set_leg(Pose& pose, int side, double hip, double knee, double ankle) {
  const int h = side > 0 ? hip_l : hip_r;
  pose.local[h] = leg_flex(hip);
  pose.local[h + 1] = leg_flex(-knee);
  pose.local[h + 2] = leg_flex(ankle);
}

/// Leg angles that lower the pelvis by `drop` with the feet flat under the hips.
double crouch_angle(const Skeleton& sk, double drop) {
  const double legs = (sk.rest[hip_l] - sk.rest[knee_l]).norm() + (sk.rest[knee_l] - sk.rest[ankle_l]).norm();
  return std::acos(std::clamp(1.0 - drop / legs, -1.0, 1.0));
}

double gait_period(const MotionSpec& m, double fps) { return m.frames / fps / std::max(1, m.cycles); }

// --- gait ---------------------------------------------------------------------------------

RootState gait_root(const Skeleton& sk, const MotionSpec& m, double fps, double t) {
  const double omega = m.turn_rate * degrees, duration = m.duration(fps);
  // Heading and path centred on the middle of the sequence: the actor crosses the origin there.
  const double tc = t - 0.5 * duration;
  RootState root;
  root.heading = omega * tc;
  double x, z;
  if (std::abs(omega) < 1e-9) {
    x = 0;
    z = m.speed * tc;
  } else {
    x = m.speed / omega * (1 - std::cos(root.heading));
    z = m.speed / omega * std::sin(root.heading);
  }
  const double s = run_amount(m.speed);
  const double phase = 2 * M_PI * t / gait_period(m, fps);
  const double bob = lerp(0.015, 0.035, s) * std::cos(2 * phase) * lerp(1.0, -1.0, s);
  const double sway = lerp(0.02, 0.008, s) * std::sin(phase);
  const Eigen::Vector3d side = rotation_y(root.heading) * Eigen::Vector3d::UnitX();
  root.position = Eigen::Vector3d(x, sk.rest[pelvis].y() - lerp(0.015, 0.05, s) + bob, z) + sway * side;
  return root;
}

void gait_pose(const Skeleton& sk, const MotionSpec& m, double fps, double t, Pose& pose) {
  const double s = run_amount(m.speed);
  const double phi = t / gait_period(m, fps);
  const double turn_lean = -std::atan(m.speed * m.turn_rate * degrees / gravity);
  const double yaw = lerp(4, 8, s) * degrees * std::sin(2 * M_PI * phi);
  pose.local[pelvis] = rot_z(turn_lean) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const double lean = lerp(3, 12, s) * degrees;
  pose.local[spine] = rot_x(lean) * Eigen::AngleAxisd(-1.5 * yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.local[neck] = rot_x(-0.8 * lean);
  for (int side : {+1, -1}) {
    const double p = 2 * M_PI * (phi + (side > 0 ? 0.0 : 0.5));
    const double swing = std::pow(std::max(0.0, std::cos(p)), 2);
    const double hip = lerp(2, 5, s) * degrees + lerp(24, 32, s) * degrees * std::sin(p);
    const double knee = lerp(6, 22, s) * degrees + (lerp(55, 95, s) - lerp(6, 22, s)) * degrees * swing;
    const double ankle = -8 * degrees * swing + 6 * degrees * std::sin(p);
    set_leg(pose, side, hip, knee, ankle);
    const double arm = -lerp(18, 40, s) * degrees * std::sin(p);
    const double elbow = lerp(15, 85, s) * degrees + 8 * degrees * std::sin(p + 0.5);
    set_arm(pose, sk, side, lerp(22, 14, s) * degrees, arm, elbow);
  }
}

// --- jump ---------------------------------------------------------------------------------

struct JumpTimes {
  double takeoff, landing, flight;
};
JumpTimes jump_times(const MotionSpec& m, double fps) {
  const double flight = 2 * std::sqrt(2 * m.jump_height / gravity);
  const double takeoff = 0.5 * m.duration(fps) - 0.5 * flight + 0.05;
  return {takeoff, takeoff + flight, flight};
}

constexpr double crouch_window = 0.35, landing_window = 0.40;

double jump_crouch(const MotionSpec& m, const JumpTimes& times, double t) {
  const double before = 0.10 + 0.25 * m.jump_height + 0.05 * m.jump_distance;
  const double after = 0.06 + 0.20 * m.jump_height + 0.05 * m.jump_distance;
  if (t > times.takeoff - crouch_window && t < times.takeoff)
    return before * std::pow(std::sin(M_PI * (t - (times.takeoff - crouch_window)) / crouch_window), 2);
  if (t > times.landing && t < times.landing + landing_window)
    return after * std::pow(std::sin(M_PI * (t - times.landing) / landing_window), 2);
  return 0.0;
}

double flight_progress(const JumpTimes& times, double t) {
  return std::clamp((t - times.takeoff) / times.flight, 0.0, 1.0);
}

RootState jump_root(const Skeleton& sk, const MotionSpec& m, double fps, double t) {
  const JumpTimes times = jump_times(m, fps);
  const double u = flight_progress(times, t);
  const bool flying = t > times.takeoff && t < times.landing;
  RootState root;
  const double rise = flying ? m.jump_height * 4 * u * (1 - u) : 0.0;
  root.position = Eigen::Vector3d(0, sk.rest[pelvis].y() - 0.015 - jump_crouch(m, times, t) + rise,
                                  m.jump_distance * (u - 0.5));
  return root;
}

void jump_pose(const Skeleton& sk, const MotionSpec& m, double fps, double t, Pose& pose) {
  const JumpTimes times = jump_times(m, fps);
  const double crouch = jump_crouch(m, times, t);
  const double theta = crouch_angle(sk, crouch);
  const double u = flight_progress(times, t);
  const bool flying = t > times.takeoff && t < times.landing;
  const double tuck = flying ? std::sin(M_PI * u) * (0.3 + m.jump_height) : 0.0;
  for (int side : {+1, -1}) set_leg(pose, side, theta + 0.5 * tuck, 2 * theta + tuck, theta + 0.3 * tuck);
  pose.local[spine] = rot_x(0.9 * theta + 0.2 * tuck);
  pose.local[neck] = rot_x(-0.6 * theta);
  // Arms swing back in the crouch, forward and up through the flight, forward on landing.
  double arm = 0.0;
  if (t < times.takeoff) arm = -1.6 * theta;
  else if (flying) arm = (60 + 100 * m.jump_height) * degrees * std::sin(M_PI * std::min(1.0, 1.5 * u));
  else arm = 0.9 * theta;
  for (int side : {+1, -1}) set_arm(pose, sk, side, 18 * degrees, arm, 20 * degrees + 0.5 * theta);
}

// --- reach --------------------------------------------------------------------------------

double reach_amount(const MotionSpec& m, double fps, double t) {
  const double u = t / m.duration(fps);
  return smoothstep(0.12, 0.45, u) * (1 - smoothstep(0.6, 0.9, u));
}

double reach_crouch(const MotionSpec& m) { return 0.22 * std::clamp((1.15 - m.reach_height) / 0.4, 0.0, 1.0); }

RootState reach_root(const Skeleton& sk, const MotionSpec& m, double fps, double t) {
  RootState root;
  root.position = Eigen::Vector3d(0, sk.rest[pelvis].y() - 0.015 - reach_crouch(m) * reach_amount(m, fps, t), 0);
  return root;
}

void reach_pose(const Skeleton& sk, const MotionSpec& m, double fps, double t, Pose& pose) {
  const double a = reach_amount(m, fps, t);
  const double crouch = reach_crouch(m) * a;
  const double theta = crouch_angle(sk, crouch);
  for (int side : {+1, -1}) set_leg(pose, side, theta, 2 * theta, theta);
  const double lean = (crouch / 0.22) * 30 * degrees;
  pose.local[spine] = rot_x(lean);
  // Right shoulder angle from hanging towards a target 0.45 m in front at reach_height.
  const Eigen::Vector3d shoulder = sk.rest[shoulder_r];
  const double dy = m.reach_height + crouch - shoulder.y(), dz = 0.45 * sk.height / 1.75;
  const double target = std::atan2(dz, -dy) - lean;
  set_arm(pose, sk, +1, 20 * degrees, 0.0, 15 * degrees);
  pose.local[shoulder_r] = leg_flex(a * target) * rot_z((20 + 5 * a) * degrees);  // right arm: +z lowers it
  pose.local[elbow_r] = flex(sk, elbow_r, (15 - 5 * a) * degrees);
}

}  // namespace

std::string family_name(MotionFamily family) {
  switch (family) {
    case MotionFamily::gait: return "gait";
    case MotionFamily::jump: return "jump";
    case MotionFamily::reach: return "reach";
  }
  return "gait";
}

MotionFamily family_from_name(const std::string& name) {
  if (name == "gait") return MotionFamily::gait;
  if (name == "jump") return MotionFamily::jump;
  if (name == "reach") return MotionFamily::reach;
  throw core::bad_arguments("unknown motion family '" + name + "' (gait, jump or reach)");
}

core::Json motion_to_json(const MotionSpec& m) {
  core::Json entry = {{"name", m.name}, {"family", family_name(m.family)}, {"frames", m.frames}};
  switch (m.family) {
    case MotionFamily::gait:
      entry.update({{"cycles", m.cycles}, {"speed", m.speed}, {"turn_rate", m.turn_rate}});
      break;
    case MotionFamily::jump:
      entry.update({{"jump_height", m.jump_height}, {"jump_distance", m.jump_distance}});
      break;
    case MotionFamily::reach: entry["reach_height"] = m.reach_height; break;
  }
  return entry;
}

MotionSpec motion_from_json(const core::Json& entry, const std::string& source) {
  MotionSpec m;
  auto fail = [&](const std::string& what) { return core::bad_arguments(source + ": sequence '" + m.name + "': " + what); };
  try {
    m.name = entry.at("name").get<std::string>();
    m.family = family_from_name(entry.value("family", std::string("gait")));
    m.frames = entry.at("frames").get<int>();
    m.cycles = entry.value("cycles", m.cycles);
    m.speed = entry.value("speed", m.speed);
    m.turn_rate = entry.value("turn_rate", m.turn_rate);
    m.jump_height = entry.value("jump_height", m.jump_height);
    m.jump_distance = entry.value("jump_distance", m.jump_distance);
    m.reach_height = entry.value("reach_height", m.reach_height);
  } catch (const core::Json::exception& e) {
    throw core::bad_arguments(source + ": a sequence entry is malformed: " + e.what());
  }
  if (m.name.empty() || m.name.find_first_of("/\\ ") != std::string::npos) throw fail("bad sequence name");
  if (m.frames < 2) throw fail("needs at least 2 frames");
  if (m.cycles < 1) throw fail("cycles must be ≥ 1");
  if (m.family == MotionFamily::gait && !(m.speed > 0 && m.speed <= 6)) throw fail("speed must be in (0, 6] m/s");
  if (m.family == MotionFamily::jump && !(m.jump_height > 0.02 && m.jump_height <= 0.8 && m.jump_distance >= 0))
    throw fail("jump_height must be in (0.02, 0.8] m and jump_distance ≥ 0");
  if (m.family == MotionFamily::reach && !(m.reach_height >= 0.7 && m.reach_height <= 2.2))
    throw fail("reach_height must be in [0.7, 2.2] m");
  return m;
}

RootState root_at(const Skeleton& sk, const MotionSpec& m, double fps, double time) {
  switch (m.family) {
    case MotionFamily::gait: return gait_root(sk, m, fps, time);
    case MotionFamily::jump: return jump_root(sk, m, fps, std::clamp(time, 0.0, m.duration(fps)));
    case MotionFamily::reach: return reach_root(sk, m, fps, std::clamp(time, 0.0, m.duration(fps)));
  }
  return {};
}

Pose pose_at(const Skeleton& sk, const MotionSpec& m, double fps, double time) {
  Pose pose(sk.size());
  const RootState root = root_at(sk, m, fps, time);
  pose.root = root.position;
  pose.heading = root.heading;
  const double t = m.cyclic() ? time : std::clamp(time, 0.0, m.duration(fps));
  switch (m.family) {
    case MotionFamily::gait: gait_pose(sk, m, fps, t, pose); break;
    case MotionFamily::jump: jump_pose(sk, m, fps, t, pose); break;
    case MotionFamily::reach: reach_pose(sk, m, fps, t, pose); break;
  }
  return pose;
}

}  // namespace surfcap::synth
