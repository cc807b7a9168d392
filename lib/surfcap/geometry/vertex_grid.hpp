#pragma once
// Points binned on a uniform grid for radius searches: every point within one cell size of a
// query lies in the 27 cells around it.

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace surfcap::geometry {

class VertexGrid {
 public:
  /// Bins the rows of `V` (kept by reference) in cells of size `cell`.
  VertexGrid(const Eigen::MatrixXd& V, double cell) : V_(V), cell_(cell) {
    for (long v = 0; v < V.rows(); ++v) bins_[key(V.row(v).transpose())].push_back(v);
  }
  /// Calls visit(row) for every point in the 27 cells around `p` (a superset of those within `cell`).
  template <class Visit>
  void around(const Eigen::Vector3d& p, Visit&& visit) const {
    const Eigen::Vector3i c = (p / cell_).array().floor().cast<int>();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = bins_.find(pack(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == bins_.end()) continue;
          for (const long v : it->second) visit(v);
        }
  }

 private:
  static std::int64_t pack(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x() & 0x1FFFFF) << 42) | (static_cast<std::int64_t>(c.y() & 0x1FFFFF) << 21) |
           static_cast<std::int64_t>(c.z() & 0x1FFFFF);
  }
  std::int64_t key(const Eigen::Vector3d& p) const { return pack((p / cell_).array().floor().cast<int>()); }
  const Eigen::MatrixXd& V_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<long>> bins_;
};

}  // namespace surfcap::geometry
