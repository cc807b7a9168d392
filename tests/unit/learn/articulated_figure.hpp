#pragma once
// A procedural articulated figure for tests and benchmarks: a T-posed body (torso, head, two
// arms, two legs as capsules) meshed by surface nets, posed by linear blend skinning with
// two-bone limbs, plus a pose-driven muscle bulge (non-rigid detail a learnt space can hold).
// Header-only so unit tests and benchmarks share it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "surfcap/core/database.hpp"

namespace surfcap::testing {

struct FigureBone {
  Eigen::Vector3d head, tail;
  int parent;
  double radius;
};

/// Bones: 0 spine, 1 neck, 2/3 upper/lower arm left (+x), 4/5 right, 6/7 upper/lower leg left, 8/9 right.
inline std::vector<FigureBone> figure_bones() {
  using V = Eigen::Vector3d;
  return {{V(0, 0.95, 0), V(0, 1.38, 0), -1, 0.16},     {V(0, 1.45, 0), V(0, 1.68, 0), 0, 0.10},
          {V(0.17, 1.36, 0), V(0.45, 1.36, 0), 0, 0.06}, {V(0.45, 1.36, 0), V(0.74, 1.36, 0), 2, 0.055},
          {V(-0.17, 1.36, 0), V(-0.45, 1.36, 0), 0, 0.06}, {V(-0.45, 1.36, 0), V(-0.74, 1.36, 0), 4, 0.055},
          {V(0.09, 0.90, 0), V(0.10, 0.50, 0), 0, 0.075},  {V(0.10, 0.50, 0), V(0.10, 0.10, 0), 6, 0.065},
          {V(-0.09, 0.90, 0), V(-0.10, 0.50, 0), 0, 0.075}, {V(-0.10, 0.50, 0), V(-0.10, 0.10, 0), 8, 0.065}};
}

inline double segment_distance(const Eigen::Vector3d& p, const FigureBone& b, double* t_out = nullptr) {
  const Eigen::Vector3d d = b.tail - b.head;
  const double t = std::clamp((p - b.head).dot(d) / d.squaredNorm(), 0.0, 1.0);
  if (t_out) *t_out = t;
  return (p - (b.head + t * d)).norm();
}

/// The rest-pose mesh by naive surface nets on the capsules' signed distance (spacing h metres).
inline core::Mesh make_figure_mesh(double h) {
  const auto bones = figure_bones();
  auto sdf = [&](const Eigen::Vector3d& p) {
    double d = 1e9;
    for (const auto& b : bones) d = std::min(d, segment_distance(p, b) - b.radius);
    return d;
  };
  const Eigen::Vector3d lo(-0.9, -0.05, -0.25);
  const int nx = static_cast<int>(1.8 / h) + 2, ny = static_cast<int>(1.85 / h) + 2, nz = static_cast<int>(0.5 / h) + 2;
  auto at = [&](int i, int j, int k) -> Eigen::Vector3d { return lo + h * Eigen::Vector3d(i, j, k); };
  std::vector<double> value(static_cast<std::size_t>(nx) * ny * nz);
  auto index = [&](int i, int j, int k) { return (static_cast<std::size_t>(k) * ny + j) * nx + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) value[index(i, j, k)] = sdf(at(i, j, k));
  std::map<std::size_t, int> cell_vertex;
  std::vector<Eigen::Vector3d> positions;
  auto cell = [&](int i, int j, int k) -> int {  // vertex of cell (i,j,k): mean of its edge crossings
    const std::size_t key = index(i, j, k);
    auto found = cell_vertex.find(key);
    if (found != cell_vertex.end()) return found->second;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) {
        const int diff = std::abs(corner[a][0] - corner[b][0]) + std::abs(corner[a][1] - corner[b][1]) +
                         std::abs(corner[a][2] - corner[b][2]);
        if (diff != 1) continue;
        const double va = value[index(i + corner[a][0], j + corner[a][1], k + corner[a][2])];
        const double vb = value[index(i + corner[b][0], j + corner[b][1], k + corner[b][2])];
        if ((va < 0) == (vb < 0)) continue;
        const double t = va / (va - vb);
        sum += (1 - t) * at(i + corner[a][0], j + corner[a][1], k + corner[a][2]) +
               t * at(i + corner[b][0], j + corner[b][1], k + corner[b][2]);
        ++count;
      }
    positions.push_back(sum / count);
    cell_vertex[key] = static_cast<int>(positions.size()) - 1;
    return cell_vertex[key];
  };
  std::vector<Eigen::Vector3i> faces;
  auto quad = [&](int a, int b, int c, int d, bool flip) {
    if (flip) std::swap(b, d);
    // Split along the shorter diagonal.
    if ((positions[a] - positions[c]).squaredNorm() <= (positions[b] - positions[d]).squaredNorm()) {
      faces.emplace_back(a, b, c), faces.emplace_back(a, c, d);
    } else {
      faces.emplace_back(a, b, d), faces.emplace_back(b, c, d);
    }
  };
  for (int k = 1; k < nz - 1; ++k)
    for (int j = 1; j < ny - 1; ++j)
      for (int i = 1; i < nx - 1; ++i) {
        const bool inside = value[index(i, j, k)] < 0;
        if (i + 1 < nx && inside != (value[index(i + 1, j, k)] < 0))  // x edge: cells around it in y, z
          quad(cell(i, j - 1, k - 1), cell(i, j, k - 1), cell(i, j, k), cell(i, j - 1, k), !inside);
        if (j + 1 < ny && inside != (value[index(i, j + 1, k)] < 0))
          quad(cell(i - 1, j, k - 1), cell(i - 1, j, k), cell(i, j, k), cell(i, j, k - 1), !inside);
        if (k + 1 < nz && inside != (value[index(i, j, k + 1)] < 0))
          quad(cell(i - 1, j - 1, k), cell(i, j - 1, k), cell(i, j, k), cell(i - 1, j, k), !inside);
      }
  core::Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) mesh.V.row(static_cast<Eigen::Index>(v)) = positions[v].transpose();
  mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  return mesh;
}

/// Joint angles (radians) of one pose: per bone a rotation vector about its head.
using FigurePose = std::array<Eigen::Vector3d, 10>;

/// Smooth random motion: every joint follows its own sum of sinusoids (limbs uncorrelated).
inline std::vector<FigurePose> figure_motion(int frames, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Per bone and axis: range (centre, amplitude) in degrees.
  const double range[10][3][2] = {{{0, 12}, {0, 15}, {0, 8}},  {{0, 20}, {0, 25}, {0, 15}},
                                  {{0, 0}, {0, 35}, {-15, 45}}, {{0, 0}, {-50, 50}, {0, 0}},
                                  {{0, 0}, {0, 35}, {15, 45}},  {{0, 0}, {50, 50}, {0, 0}},
                                  {{-10, 40}, {0, 0}, {8, 12}}, {{45, 45}, {0, 0}, {0, 0}},
                                  {{-10, 40}, {0, 0}, {-8, 12}}, {{45, 45}, {0, 0}, {0, 0}}};
  double frequency[10][3], phase[10][3];
  for (int b = 0; b < 10; ++b)
    for (int a = 0; a < 3; ++a) frequency[b][a] = 0.5 + 2.0 * unit(random), phase[b][a] = 6.283 * unit(random);
  std::vector<FigurePose> poses(static_cast<std::size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / frames * 6.283;
    for (int b = 0; b < 10; ++b)
      for (int a = 0; a < 3; ++a)
        poses[f][b][a] = (range[b][a][0] + range[b][a][1] * std::sin(frequency[b][a] * t + phase[b][a])) * M_PI / 180;
  }
  return poses;
}

/// Linear blend skinning of the rest mesh with a bulge of the upper limbs driven by the bend.
inline Eigen::MatrixXd pose_figure(const Eigen::MatrixXd& rest, const FigurePose& pose) {
  const auto bones = figure_bones();
  std::vector<Eigen::Isometry3d> global(bones.size());
  for (std::size_t b = 0; b < bones.size(); ++b) {
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    const double angle = pose[b].norm();
    local.translate(bones[b].head);
    if (angle > 0) local.rotate(Eigen::AngleAxisd(angle, pose[b] / angle));
    local.translate(-bones[b].head);
    global[b] = bones[b].parent >= 0 ? global[bones[b].parent] * local : local;
  }
  Eigen::MatrixXd out(rest.rows(), 3);
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Eigen::Vector3d p = rest.row(v).transpose();
    std::array<double, 10> distance, along;
    double nearest = 1e9;
    for (std::size_t b = 0; b < bones.size(); ++b)
      nearest = std::min(nearest, distance[b] = segment_distance(p, bones[b], &along[b]) - bones[b].radius);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double total = 0;
    for (std::size_t b = 0; b < bones.size(); ++b) {
      const double w = std::exp(-(distance[b] - nearest) / 0.025);
      if (w < 1e-4) continue;
      Eigen::Vector3d q = p;
      // Muscle bulge of an upper limb (bones 2, 4, 6, 8) with the bend of its lower limb.
      if (b == 2 || b == 4 || b == 6 || b == 8) {
        const Eigen::Vector3d axis = (bones[b].tail - bones[b].head).normalized();
        Eigen::Vector3d radial = p - bones[b].head - (p - bones[b].head).dot(axis) * axis;
        if (radial.norm() > 1e-9) q += 0.02 * std::abs(std::sin(pose[b + 1].norm())) *
                                        std::pow(std::sin(M_PI * along[b]), 2) * radial.normalized();
      }
      sum += w * (global[b] * q);
      total += w;
    }
    out.row(v) = (sum / total).transpose();
  }
  return out;
}

/// An aligned database of one sequence "motion" of the figure (centred frames, zero root motion).
inline core::AlignedDatabase figure_database(double h, int frames, unsigned seed) {
  core::AlignedDatabase db;
  db.template_mesh = make_figure_mesh(h);
  core::AlignedSequence sequence;
  sequence.name = "motion";
  for (const auto& pose : figure_motion(frames, seed)) {
    sequence.frames.push_back(pose_figure(db.template_mesh.V, pose));
    sequence.root_motion.push_back({});
  }
  db.sequences.push_back(std::move(sequence));
  db.root_sequence = "motion";
  return db;
}

}  // namespace surfcap::testing
