#pragma once
// The template split into surface patches for rigid patch matching (casas2011 §3.2, Cagniart et
// al. 2010): seeds by farthest-point sampling along mesh edges, each vertex to its nearest seed
// (edge geodesic Voronoi cells). 30 patches at the coarsest level, doubling each level.

#include <Eigen/Core>
#include <vector>

namespace surfcap::align {

struct PatchSet {
  std::vector<int> label;                  ///< per vertex: its patch
  std::vector<std::vector<int>> vertices;  ///< per patch: its vertices (ascending)
  int count() const { return static_cast<int>(vertices.size()); }
};

/// `count` patches of the surface (V n×3, F m×3). Deterministic: the first seed is vertex 0's
/// farthest vertex, ties go to the lower index. Every vertex gets a patch (a component without a
/// seed gets its own seed). count ≥ 1.
PatchSet surface_patches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int count);

/// The patch sets of `levels` levels: initial, 2·initial, 4·initial, … (capped at n/4 patches).
std::vector<PatchSet> patch_hierarchy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int initial, int levels);

}  // namespace surfcap::align
