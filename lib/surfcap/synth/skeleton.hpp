#pragma once
// The synthetic actor's skeleton: 21 joints, rest pose in a wide A-pose facing +z, y up, metres.
// A pose is a local rotation per joint (relative to the rest orientation, which is world-aligned
// for every joint) plus the root's world position and heading.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace surfcap::synth {

enum Joint : int {
  pelvis, spine, chest, neck, head,
  clavicle_l, shoulder_l, elbow_l, wrist_l,
  clavicle_r, shoulder_r, elbow_r, wrist_r,
  hip_l, knee_l, ankle_l, toe_l,
  hip_r, knee_r, ankle_r, toe_r,
  joint_count
};

struct Skeleton {
  std::vector<std::string> names;
  std::vector<int> parents;               ///< −1 for the root (pelvis)
  std::vector<Eigen::Vector3d> rest;      ///< rest-pose joint positions
  std::vector<Eigen::Vector3d> bone_end;  ///< rest-pose end of each joint's bone (its main child or tip)
  double height = 1.75;

  int size() const { return static_cast<int>(names.size()); }
  /// Unit rest direction of joint j's bone.
  Eigen::Vector3d bone_direction(int j) const { return (bone_end[j] - rest[j]).normalized(); }
};

/// The skeleton of an actor `height` metres tall (proportions scale with it).
Skeleton make_skeleton(double height = 1.75);

struct Pose {
  std::vector<Eigen::Matrix3d> local;  ///< per joint, relative to the rest orientation
  Eigen::Vector3d root = Eigen::Vector3d::Zero();  ///< world position of the pelvis joint
  double heading = 0;                  ///< radians about +y, 0 faces +z
  explicit Pose(int joints = joint_count) : local(static_cast<std::size_t>(joints), Eigen::Matrix3d::Identity()) {}
};

/// Per joint: the rigid map of rest space to world space, x ↦ rotation·x + translation.
struct JointTransforms {
  std::vector<Eigen::Matrix3d> rotation;
  std::vector<Eigen::Vector3d> translation;
  std::vector<Eigen::Vector3d> position;  ///< world joint positions
};

JointTransforms forward_kinematics(const Skeleton& skeleton, const Pose& pose);

/// Rotation about +y by `angle` (right-handed: +z turns towards +x).
Eigen::Matrix3d rotation_y(double angle);
/// Rotation of joint j's bone forward (towards +z) by `angle`, about the axis bone × z.
Eigen::Matrix3d flex(const Skeleton& skeleton, int joint, double angle);

}  // namespace surfcap::synth
