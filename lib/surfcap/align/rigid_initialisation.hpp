#pragma once
// Whole-body rigid initialisation of a pairwise alignment (casas2011 §3.2): the parent's pose
// moved onto the child's reconstruction before the non-rigid levels.

#include <Eigen/Core>

#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

class AlignmentTemplate;
struct PairwiseOptions;

/// The colours of a surface and of its target (per vertex, 0..1) for scoring rigid fits.
struct RigidColours {
  const Eigen::MatrixXd* surface = nullptr;  ///< per surface vertex
  const Eigen::MatrixXd* target = nullptr;   ///< per target vertex
  double scale = 0;                          ///< metres per unit of RGB in the joint space
};

/// Rigid initialisation of a template surface (vertex normals `normals`) onto `target`: centroids
/// matched, ICP; if the result does not overlap, the best of `heading_samples` rotations about the
/// vertical axis (similar frames of different sequences may face differently: the shape
/// similarity is invariant to heading). With `colours` the headings are compared in the joint
/// position-colour space of the colour-aware patch matching: an open, phantom-laden visual hull
/// is nearly as close to the body turned half round as to the body itself, its colours are not.
RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options, const RigidColours& colours = {});

}  // namespace surfcap::align
