#pragma once
// The aligned database (DESIGN §3.2) from the aligned template of every node: the template is the
// root reconstruction, each frame centred with its root motion.

#include <Eigen/Core>

#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::align {

/// Root motion of an aligned frame relative to the template at rest: centroid (x, y, z) and the
/// heading of the best rotation about +y taking the centred template onto the centred frame.
core::RootMotion root_motion(const Eigen::MatrixXd& template_rest, const Eigen::MatrixXd& world);

/// The database of `frames` (node order) from the template surface of each node (`world`, metres),
/// rooted at the capture's `root_sequence`:`root_frame`.
core::AlignedDatabase aligned_database(const core::Capture& capture, const similarity::FrameList& frames,
                                       const core::Mesh& template_mesh, int root_sequence, int root_frame,
                                       const std::vector<Eigen::MatrixXd>& world);

}  // namespace surfcap::align
