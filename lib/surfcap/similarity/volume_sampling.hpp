#pragma once
// Regular sampling of the volume a closed surface encloses, for meshes of any connectivity.

#include <Eigen/Core>

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

}  // namespace surfcap::similarity
