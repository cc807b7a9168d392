#include "surfcap/synth/skeleton.hpp"

#include <cmath>

namespace surfcap::synth {

Skeleton make_skeleton(double height) {
  const double s = height / 1.75;
  Skeleton sk;
  sk.height = height;
  sk.names = {"pelvis", "spine", "chest", "neck", "head",
              "clavicle_l", "shoulder_l", "elbow_l", "wrist_l",
              "clavicle_r", "shoulder_r", "elbow_r", "wrist_r",
              "hip_l", "knee_l", "ankle_l", "toe_l",
              "hip_r", "knee_r", "ankle_r", "toe_r"};
  sk.parents = {-1, pelvis, spine, chest, neck,
                chest, clavicle_l, shoulder_l, elbow_l,
                chest, clavicle_r, shoulder_r, elbow_r,
                pelvis, hip_l, knee_l, ankle_l,
                pelvis, hip_r, knee_r, ankle_r};
  sk.rest.resize(joint_count);
  sk.bone_end.resize(joint_count);
  auto at = [s](double x, double y, double z) -> Eigen::Vector3d { return Eigen::Vector3d(x, y, z) * s; };
  sk.rest[pelvis] = at(0, 0.95, 0);
  sk.rest[spine] = at(0, 1.07, -0.01);
  sk.rest[chest] = at(0, 1.26, -0.01);
  sk.rest[neck] = at(0, 1.49, -0.01);
  sk.rest[head] = at(0, 1.56, 0.0);
  // A-pose: arms 50° below horizontal, so the surface of the arms stays clear of the torso.
  const Eigen::Vector3d arm_l = Eigen::Vector3d(std::cos(50 * M_PI / 180), -std::sin(50 * M_PI / 180), 0);
  for (int side = 0; side < 2; ++side) {
    const double x = side == 0 ? 1 : -1;
    const int clavicle = side == 0 ? clavicle_l : clavicle_r;
    const Eigen::Vector3d direction(x * arm_l.x(), arm_l.y(), 0);
    sk.rest[clavicle] = at(x * 0.03, 1.43, -0.01);
    sk.rest[clavicle + 1] = at(x * 0.18, 1.43, -0.01);
    sk.rest[clavicle + 2] = sk.rest[clavicle + 1] + 0.28 * s * direction;
    sk.rest[clavicle + 3] = sk.rest[clavicle + 2] + 0.25 * s * direction;
    sk.bone_end[clavicle] = sk.rest[clavicle + 1];
    sk.bone_end[clavicle + 1] = sk.rest[clavicle + 2];
    sk.bone_end[clavicle + 2] = sk.rest[clavicle + 3];
    sk.bone_end[clavicle + 3] = sk.rest[clavicle + 3] + 0.10 * s * direction;
    const int hip = side == 0 ? hip_l : hip_r;
    sk.rest[hip] = at(x * 0.095, 0.91, 0);
    sk.rest[hip + 1] = at(x * 0.10, 0.50, 0.01);
    sk.rest[hip + 2] = at(x * 0.10, 0.09, -0.01);
    sk.rest[hip + 3] = at(x * 0.10, 0.03, 0.13);
    sk.bone_end[hip] = sk.rest[hip + 1];
    sk.bone_end[hip + 1] = sk.rest[hip + 2];
    sk.bone_end[hip + 2] = sk.rest[hip + 3];
    sk.bone_end[hip + 3] = at(x * 0.10, 0.03, 0.19);
  }
  sk.bone_end[pelvis] = sk.rest[spine];
  sk.bone_end[spine] = sk.rest[chest];
  sk.bone_end[chest] = sk.rest[neck];
  sk.bone_end[neck] = sk.rest[head];
  sk.bone_end[head] = at(0, 1.75, 0.0);
  return sk;
}

JointTransforms forward_kinematics(const Skeleton& skeleton, const Pose& pose) {
  const int n = skeleton.size();
  JointTransforms result;
  result.rotation.resize(static_cast<std::size_t>(n));
  result.translation.resize(static_cast<std::size_t>(n));
  result.position.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {  // parents come before children
    const int p = skeleton.parents[static_cast<std::size_t>(j)];
    if (p < 0) {
      result.rotation[j] = rotation_y(pose.heading) * pose.local[j];
      result.position[j] = pose.root;
    } else {
      result.rotation[j] = result.rotation[p] * pose.local[j];
      result.position[j] = result.position[p] + result.rotation[p] * (skeleton.rest[j] - skeleton.rest[p]);
    }
    result.translation[j] = result.position[j] - result.rotation[j] * skeleton.rest[j];
  }
  return result;
}

Eigen::Matrix3d rotation_y(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

Eigen::Matrix3d flex(const Skeleton& skeleton, int joint, double angle) {
  const Eigen::Vector3d axis = skeleton.bone_direction(joint).cross(Eigen::Vector3d::UnitZ()).normalized();
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

}  // namespace surfcap::synth
