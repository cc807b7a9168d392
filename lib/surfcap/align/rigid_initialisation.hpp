#pragma once
// Whole-body rigid initialisation of a pairwise alignment (casas2011 §3.2): the parent's pose
// moved onto the child's reconstruction before the non-rigid levels.

#include <Eigen/Core>

#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

class AlignmentTemplate;
struct PairwiseOptions;

/// Rigid initialisation of a template surface (vertex normals `normals`) onto `target`: centroids
/// matched, ICP; if the result does not overlap, the best of `heading_samples` rotations about the
/// vertical axis (similar frames of different sequences may face differently: the shape
/// similarity is invariant to heading).
RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options);

}  // namespace surfcap::align
