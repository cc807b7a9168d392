#pragma once
// A test body: an asymmetric ellipsoid (so no rigid motion maps it onto itself) tessellated at
// any resolution, and a smooth known deformation (bend + twist + translation) defined on space,
// so every template vertex has a true position in the deformed frame.

#include <Eigen/Geometry>
#include <cmath>

#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::align::testing {

inline Eigen::Vector3d ellipsoid_axes() { return {0.22, 0.9, 0.14}; }

/// A closed UV sphere of radius 1 (self-contained: benchmarks use it too).
inline core::Mesh unit_sphere(int rings, int segments) {
  core::Mesh mesh;
  mesh.V.resize((rings - 1) * segments + 2, 3);
  mesh.V.row(0) << 0, 1, 0;
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      mesh.V.row(1 + (r - 1) * segments + s) << std::sin(theta) * std::cos(phi), std::cos(theta),
          std::sin(theta) * std::sin(phi);
    }
  const int south = (rings - 1) * segments + 1;
  mesh.V.row(south) << 0, -1, 0;
  std::vector<Eigen::Vector3i> faces;
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) faces.emplace_back(0, at(1, s + 1), at(1, s));
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      faces.emplace_back(at(r, s), at(r, s + 1), at(r + 1, s));
      faces.emplace_back(at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
    }
  for (int s = 0; s < segments; ++s) faces.emplace_back(south, at(rings - 1, s), at(rings - 1, s + 1));
  mesh.F.resize(static_cast<long>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<long>(f)) = faces[f].transpose();
  return mesh;
}

/// Tessellations with different rings/segments give different connectivity on the same surface.
inline core::Mesh ellipsoid(int rings, int segments) {
  core::Mesh mesh = unit_sphere(rings, segments);
  const Eigen::MatrixXd unit = mesh.V;
  const Eigen::Vector3d axes = ellipsoid_axes();
  for (long v = 0; v < mesh.V.rows(); ++v) {
    mesh.V.row(v) = mesh.V.row(v).cwiseProduct(axes.transpose());
    // Bumps at different heights and sides break the symmetries, like a body's features.
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    const Eigen::Vector3d direction = unit.row(v).transpose();
    double bump = 0;
    const double centres[4][3] = {{1, 0.3, 0}, {0, 0.5, 1}, {-0.7, -0.3, 0.7}, {0.3, -0.6, -1}};
    for (const auto& c : centres) {
      const Eigen::Vector3d centre = Eigen::Vector3d(c[0], 0, c[2]).normalized();
      const double angular = (Eigen::Vector3d(direction.x(), 0, direction.z()).normalized() - centre).squaredNorm();
      bump += 0.04 * std::exp(-angular / 0.15 - (p.y() - c[1]) * (p.y() - c[1]) / 0.02);
    }
    mesh.V.row(v) += bump * Eigen::Vector3d(direction.x(), 0, direction.z()).transpose();
  }
  return mesh;
}

/// Bends about z by `bend` radians per metre of height, twists about y, then moves.
inline Eigen::Vector3d deform_point(const Eigen::Vector3d& p, double bend, double twist, const Eigen::Vector3d& move) {
  const Eigen::Matrix3d twist_rotation = Eigen::AngleAxisd(twist * p.y(), Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d bend_rotation = Eigen::AngleAxisd(bend * p.y(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return bend_rotation * (twist_rotation * p) + move;
}

inline Eigen::MatrixXd deform_points(const Eigen::MatrixXd& V, double bend, double twist, const Eigen::Vector3d& move) {
  Eigen::MatrixXd out(V.rows(), 3);
  for (long v = 0; v < V.rows(); ++v) out.row(v) = deform_point(V.row(v).transpose(), bend, twist, move).transpose();
  return out;
}

}  // namespace surfcap::align::testing
