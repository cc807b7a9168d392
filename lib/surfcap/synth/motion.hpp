#pragma once
// Procedural motions of the synthetic actor, each a family whose members differ in one
// high-level parameter: gait (speed; turn rate), jump (height; distance), reach (hand height).
// A motion is a pure function of time, so any instant can be evaluated (the garment dynamics
// look back in time) and cyclic motions are exactly cyclic.

#include <string>

#include "surfcap/core/json_document.hpp"
#include "surfcap/synth/skeleton.hpp"

namespace surfcap::synth {

enum class MotionFamily { gait, jump, reach };

struct MotionSpec {
  std::string name = "walk";
  MotionFamily family = MotionFamily::gait;
  int frames = 28;
  int cycles = 1;             ///< gait: the centred pose repeats every frames/cycles frames
  double speed = 1.3;         ///< gait: m/s (walk ≈ 1.3, run ≈ 3)
  double turn_rate = 0;       ///< gait: degrees per second, > 0 turns left (counter-clockwise from above)
  double jump_height = 0.25;  ///< jump: apex rise of the pelvis, metres
  double jump_distance = 0.3; ///< jump: forward travel in flight, metres
  double reach_height = 1.2;  ///< reach: target height of the right hand, metres

  bool cyclic() const { return family == MotionFamily::gait; }
  double duration(double fps) const { return frames / fps; }
};

std::string family_name(MotionFamily family);
MotionFamily family_from_name(const std::string& name);  ///< bad_arguments for an unknown name

core::Json motion_to_json(const MotionSpec& motion);
MotionSpec motion_from_json(const core::Json& entry, const std::string& source);

/// Where the root (pelvis joint) is and which way it faces at `time` seconds from the start.
struct RootState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double heading = 0;
};
RootState root_at(const Skeleton& skeleton, const MotionSpec& motion, double fps, double time);

/// The full pose at `time` seconds (time may lie outside the sequence: gaits continue
/// periodically, jumps and reaches hold their first / last pose).
Pose pose_at(const Skeleton& skeleton, const MotionSpec& motion, double fps, double time);

}  // namespace surfcap::synth
