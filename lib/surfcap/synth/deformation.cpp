#include "surfcap/synth/deformation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace surfcap::synth {
namespace {

/// Muscle and cloth bunching at a flexed elbow or knee: a ring at the joint and a bulge on the
/// flexing side of the bone above, growing with the flexion angle.
void add_bulges(const Body& body, const Eigen::MatrixXd& normals, const Pose& pose, double amplitude,
                Eigen::MatrixXd& V) {
  const auto& sk = body.skeleton;
  for (int joint : {elbow_l, elbow_r, knee_l, knee_r}) {
    const double angle = Eigen::AngleAxisd(pose.local[joint]).angle();
    if (angle < 1e-6) continue;
    const double strength = amplitude * std::min(angle / (M_PI / 2), 1.5);
    const int upper = sk.parents[joint];
    const Eigen::Vector3d axis = sk.bone_direction(upper);
    // Elbows flex forward (+z), knees backward.
    const Eigen::Vector3d side(0, 0, (joint == knee_l || joint == knee_r) ? -1.0 : 1.0);
    const double scale = sk.height / 1.75;
    for (long v = 0; v < V.rows(); ++v) {
      const double w = body.skin_weights(v, joint) + body.skin_weights(v, upper);
      if (w < 1e-3) continue;
      const Eigen::Vector3d p = body.rest.V.row(v).transpose();
      const Eigen::Vector3d n = normals.row(v).transpose();
      const double s = (p - sk.rest[joint]).dot(axis) / scale;  // < 0 on the upper bone
      const double ring = 0.5 * std::exp(-std::pow(s / 0.045, 2));
      const double muscle = std::exp(-std::pow((s + 0.11) / 0.06, 2)) * std::max(0.0, n.dot(side));
      V.row(v) += (w * strength * (ring + muscle)) * n.transpose();
    }
  }
}

/// How far towards the skirt's side wall a vertex sits (its elliptical radius over the cone's at
/// its rest height, at most 1). The flare turns each vertex outwards about a horizontal axis through
/// the waist; without this factor the underside between the legs, where the outward direction turns
/// round the axis within a few centimetres, was torn apart (faces stretched over 100×). With it
/// the underside opens like a membrane, in proportion to the distance from the axis.
double membrane_fraction(const Body& body, long v) {
  const auto& k = body.skirt;
  const Eigen::Vector3d p = body.rest.V.row(v).transpose();
  const double t = std::clamp((k.waist_height - p.y()) / (k.waist_height - k.hem_height), 0.0, 1.0);
  const double wall = k.waist_radius + t * (k.hem_radius - k.waist_radius);
  return std::min(1.0, std::hypot(p.x(), p.z() / k.depth_scale) / wall);
}

/// The skirt rotates about its waist: more towards the hem (so it bends), by the garment state.
void add_skirt_motion(const Body& body, const GarmentState& g, Eigen::MatrixXd& V) {
  const Eigen::Vector3d hinge(0, body.skirt.waist_height, 0);
  for (long v = 0; v < V.rows(); ++v) {
    const double weight = body.garment_weight[v];
    if (weight < 1e-4) continue;
    const double amount = weight * std::pow(body.garment_depth[v], 1.5);
    Eigen::Vector3d offset = V.row(v).transpose() - hinge;
    Eigen::Vector3d radial(offset.x(), 0, offset.z());
    radial = radial.norm() > 1e-9 ? Eigen::Vector3d(radial.normalized()) : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d flare_axis = radial.cross(Eigen::Vector3d::UnitY());
    offset = Eigen::AngleAxisd(amount * g.flare * membrane_fraction(body, v), flare_axis) * offset;
    offset = Eigen::AngleAxisd(amount * g.twist, Eigen::Vector3d::UnitY()) * offset;
    const Eigen::Vector3d swing(g.swing_back, 0, g.swing_side);
    if (swing.norm() > 1e-12) offset = Eigen::AngleAxisd(amount * swing.norm(), swing.normalized()) * offset;
    V.row(v) = (hinge + offset).transpose();
  }
}

}  // namespace

Eigen::MatrixXd secondary_deformation(const Body& body, const Eigen::MatrixXd& rest_normals, const Pose& pose,
                                      const GarmentState& garment, const DeformationOptions& options) {
  Eigen::MatrixXd V = body.rest.V;
  add_bulges(body, rest_normals, pose, options.bulge, V);
  add_skirt_motion(body, garment, V);
  return V;
}

Eigen::MatrixXd skin(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& weights, const JointTransforms& joints) {
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(rest.rows(), 3);
  const long joint_total = weights.cols();
  for (long v = 0; v < rest.rows(); ++v) {
    const Eigen::Vector3d p = rest.row(v).transpose();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (long j = 0; j < joint_total; ++j) {
      const double w = weights(v, j);
      if (w == 0) continue;
      sum += w * (joints.rotation[j] * p + joints.translation[j]);
    }
    V.row(v) = sum.transpose();
  }
  return V;
}

Eigen::MatrixXd deform_body(const Body& body, const Eigen::MatrixXd& rest_normals, const Pose& pose,
                            const GarmentState& garment, const DeformationOptions& options) {
  const Eigen::MatrixXd rest = secondary_deformation(body, rest_normals, pose, garment, options);
  return skin(rest, body.skin_weights, forward_kinematics(body.skeleton, pose));
}

}  // namespace surfcap::synth
