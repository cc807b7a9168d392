#pragma once
// The mean edge length of a triangle mesh: the unit of the distance gates of alignment
// (docs/align.md: options ending in _edges) and of the tet mesh's interior spacing.

#include <Eigen/Core>

namespace surfcap::geometry {

/// Mean over the faces' three edges (an interior edge counts once per face); 0 without faces.
double mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace surfcap::geometry
