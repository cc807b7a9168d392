#include "surfcap/align/creases.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>

#include "surfcap/core/error.hpp"

namespace surfcap::align {
namespace {

/// One interior edge: its endpoints, the two faces' unit normals and the dihedral angle (> 0 only
/// when convex).
struct DihedralEdge {
  int a = 0, b = 0;
  Eigen::Vector3d n1, n2;
  double convex_angle = 0;
};

std::vector<DihedralEdge> dihedral_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd normals(F.rows(), 3);
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d p0 = V.row(F(f, 0)).transpose();
    const Eigen::Vector3d e1 = V.row(F(f, 1)).transpose() - p0;
    const Eigen::Vector3d e2 = V.row(F(f, 2)).transpose() - p0;
    const Eigen::Vector3d n = e1.cross(e2);
    const double length = n.norm();
    normals.row(f) = length > 0 ? Eigen::RowVector3d((n / length).transpose()) : Eigen::RowVector3d::Zero();
  }
  // Faces (with the vertex opposite the edge) per undirected edge, in face order: deterministic.
  std::map<std::pair<int, int>, std::vector<std::pair<long, int>>> incident;
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      incident[{std::min(a, b), std::max(a, b)}].emplace_back(f, F(f, (k + 2) % 3));
    }
  std::vector<DihedralEdge> edges;
  edges.reserve(incident.size());
  for (const auto& [ends, faces] : incident) {
    if (faces.size() != 2) continue;
    DihedralEdge edge;
    edge.a = ends.first;
    edge.b = ends.second;
    edge.n1 = normals.row(faces[0].first).transpose();
    edge.n2 = normals.row(faces[1].first).transpose();
    if (edge.n1.isZero() || edge.n2.isZero()) continue;
    // Convex: the second face's far vertex lies behind the first face's plane.
    const Eigen::Vector3d towards = V.row(faces[1].second).transpose() - V.row(edge.a).transpose();
    if (edge.n1.dot(towards) < 0) edge.convex_angle = std::acos(std::clamp(edge.n1.dot(edge.n2), -1.0, 1.0));
    edges.push_back(edge);
  }
  return edges;
}

}  // namespace

Eigen::VectorXd convex_crease_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd angles = Eigen::VectorXd::Zero(V.rows());
  for (const DihedralEdge& edge : dihedral_edges(V, F)) {
    angles(edge.a) = std::max(angles(edge.a), edge.convex_angle);
    angles(edge.b) = std::max(angles(edge.b), edge.convex_angle);
  }
  return angles;
}

std::vector<int> convex_crease_vertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_angle) {
  const Eigen::VectorXd angles = convex_crease_angles(V, F);
  std::vector<int> vertices;
  for (long v = 0; v < angles.size(); ++v)
    if (angles(v) > min_angle) vertices.push_back(static_cast<int>(v));
  return vertices;
}

std::vector<int> straight_crease_vertices(const Eigen::MatrixXd& V, const std::vector<int>& crease, double radius,
                                          double max_ratio) {
  if (max_ratio >= 1) return crease;
  // Crease sets are small (tens to a few hundred vertices): all pairs.
  std::vector<int> straight;
  const double r2 = radius * radius;
  for (const int v : crease) {
    const Eigen::RowVector3d p = V.row(v);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    int count = 0;
    for (const int u : crease) {
      const Eigen::Vector3d d = (V.row(u) - p).transpose();
      if (d.squaredNorm() > r2) continue;
      sum += d;
      outer += d * d.transpose();
      ++count;
    }
    if (count < 3) continue;
    const Eigen::Vector3d mean = sum / count;
    const Eigen::Matrix3d covariance = outer / count - mean * mean.transpose();
    const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();
    if (eigenvalues(2) > 0 && eigenvalues(1) <= max_ratio * max_ratio * eigenvalues(2)) straight.push_back(v);
  }
  return straight;
}

CreaseLines::CreaseLines(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_angle, double reach)
    : V_(V) {
  if (!(reach > 0)) throw core::internal_error("CreaseLines: reach must be > 0");
  std::vector<DihedralEdge> creases;
  for (const DihedralEdge& edge : dihedral_edges(V, F))
    if (edge.convex_angle > min_angle) creases.push_back(edge);
  double longest = 0;
  for (const DihedralEdge& edge : creases) {
    edges_.push_back({edge.a, edge.b});
    bisectors_.push_back((edge.n1 + edge.n2).normalized());
    longest = std::max(longest, (V.row(edge.a) - V.row(edge.b)).norm());
  }
  // A point within `reach` of a segment is within reach + half its length of the midpoint: one
  // cell of that size around the query's cell covers every candidate.
  cell_ = reach + 0.5 * longest;
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const Eigen::Vector3d mid = 0.5 * (V_.row(edges_[e][0]) + V_.row(edges_[e][1])).transpose();
    bins_[key((mid / cell_).array().floor().cast<int>())].push_back(static_cast<int>(e));
  }
}

std::int64_t CreaseLines::key(const Eigen::Vector3i& c) const {
  return (static_cast<std::int64_t>(c.x() & 0x1FFFFF) << 42) | (static_cast<std::int64_t>(c.y() & 0x1FFFFF) << 21) |
         static_cast<std::int64_t>(c.z() & 0x1FFFFF);
}

bool CreaseLines::closest(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, double max_distance, double min_cos,
                          Eigen::Vector3d& point) const {
  const Eigen::Vector3i c = (p / cell_).array().floor().cast<int>();
  double best = max_distance * max_distance;
  int best_edge = -1;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = bins_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
        if (it == bins_.end()) continue;
        for (const int e : it->second) {
          if (bisectors_[static_cast<std::size_t>(e)].dot(normal) < min_cos) continue;
          const Eigen::Vector3d a = V_.row(edges_[static_cast<std::size_t>(e)][0]).transpose();
          const Eigen::Vector3d b = V_.row(edges_[static_cast<std::size_t>(e)][1]).transpose();
          const Eigen::Vector3d ab = b - a;
          const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-30), 0.0, 1.0);
          const Eigen::Vector3d q = a + t * ab;
          const double d2 = (q - p).squaredNorm();
          if (d2 < best || (d2 == best && best_edge >= 0 && e < best_edge)) {
            best = d2;
            best_edge = e;
            point = q;
          }
        }
      }
  return best_edge >= 0;
}

}  // namespace surfcap::align
