#pragma once
// The body's surface in a pose: rest-space secondary deformation (skirt swing, elbow/knee
// bulges), then linear-blend skinning.

#include <Eigen/Core>

#include "surfcap/synth/body.hpp"
#include "surfcap/synth/garment.hpp"

namespace surfcap::synth {

struct DeformationOptions {
  double bulge = 0.014;  ///< metres of muscle/cloth bulge at a 90° elbow or knee
};

/// Rest-space positions after the secondary deformation (V×3).
Eigen::MatrixXd secondary_deformation(const Body& body, const Eigen::MatrixXd& rest_normals, const Pose& pose,
                                      const GarmentState& garment, const DeformationOptions& options = {});

/// World-space vertex positions of the body (V×3) in `pose` with the skirt in `garment`.
Eigen::MatrixXd deform_body(const Body& body, const Eigen::MatrixXd& rest_normals, const Pose& pose,
                            const GarmentState& garment, const DeformationOptions& options = {});

/// Linear-blend skinning of rest-space points `rest` (V×3) with `weights` (V×J).
Eigen::MatrixXd skin(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& weights, const JointTransforms& joints);

}  // namespace surfcap::synth
