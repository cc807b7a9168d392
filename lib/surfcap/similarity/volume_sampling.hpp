#pragma once
// Regular sampling of the volume a closed surface encloses, for meshes of any connectivity.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::similarity {

/// The volume inside the surface sampled on a regular grid (spacing metres): k×4 rows
/// (x, y, z, fraction). A vertical ray through each cell column is intersected with the
/// triangles and the inside intervals follow the non-zero winding rule, so small defects (a few
/// non-manifold or duplicated faces) do not flip whole columns. Along the ray the intervals are
/// exact: each cell the inside covers gives one sample at the middle of the covered part,
/// weighted by the covered fraction of the cell (so Σ fraction · spacing³ is the volume up to the
/// column discretisation). The grid is anchored at the origin.
Eigen::MatrixXd interior_samples(const core::Mesh& mesh, double spacing);

/// The same samples without storing them: the inside intervals of every column are found once,
/// then visit(x, y, z, fraction) is called for every sample, as often as needed.
class VolumeSampler {
 public:
  VolumeSampler(const core::Mesh& mesh, double spacing);

  template <class Visitor>
  void visit(Visitor&& visitor) const {
    for (const Interval& interval : intervals_) {
      for (long j = static_cast<long>(std::floor(interval.low / spacing_));
           static_cast<double>(j) * spacing_ < interval.high; ++j) {
        const double bottom = std::max(interval.low, static_cast<double>(j) * spacing_);
        const double top = std::min(interval.high, static_cast<double>(j + 1) * spacing_);
        if (top > bottom) visitor(interval.x, 0.5 * (bottom + top), interval.z, (top - bottom) / spacing_);
      }
    }
  }
  bool empty() const { return intervals_.empty(); }

 private:
  struct Interval {
    double x, z, low, high;
  };
  double spacing_;
  std::vector<Interval> intervals_;
};

}  // namespace surfcap::similarity
