#pragma once
// In-test procedural data for the blend tests: a tube ("limb") along +y, bent about z and twisted
// about y around a joint at mid-height. Poses that differ by large rotations make linear blending
// visibly shrink the geometry, which is what the non-linear blend must fix.
#include <Eigen/Geometry>
#include <cmath>

#include "surfcap/core/mesh.hpp"

namespace surfcap::blend::testing {

/// Open tube of radius `radius`, height 1 m, `rings` × `segments` vertices, y ∈ [0, 1].
inline core::Mesh make_tube(int rings = 24, int segments = 12, double radius = 0.08) {
  core::Mesh mesh;
  mesh.V.resize(rings * segments, 3);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * M_PI * s / segments;
      mesh.V.row(r * segments + s) << radius * std::cos(angle), static_cast<double>(r) / (rings - 1),
          radius * std::sin(angle);
    }
  mesh.F.resize(2 * (rings - 1) * segments, 3);
  long k = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      mesh.F.row(k++) << a, c, b;
      mesh.F.row(k++) << b, c, d;
    }
  return mesh;
}

/// The tube bent by `bend` radians about z around the joint (0, 0.5, 0) (smoothly over
/// y ∈ [0.4, 0.6]) and twisted by `twist` radians about its own axis above the joint.
inline Eigen::MatrixXd pose_tube(const core::Mesh& tube, double bend, double twist) {
  Eigen::MatrixXd V = tube.V;
  const Eigen::Vector3d joint(0, 0.5, 0);
  for (long v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = tube.V.row(v).transpose();
    const double s = std::clamp((p.y() - 0.4) / 0.2, 0.0, 1.0);
    const double smooth = s * s * (3 - 2 * s);
    const Eigen::Matrix3d twist_rotation = Eigen::AngleAxisd(twist * smooth, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Matrix3d bend_rotation = Eigen::AngleAxisd(bend * smooth, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    V.row(v) = (joint + bend_rotation * (twist_rotation * (p - joint))).transpose();
  }
  return V;
}

}  // namespace surfcap::blend::testing
