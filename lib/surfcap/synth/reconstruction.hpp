#pragma once
// What a studio's reconstruction of one frame looks like: the true surface remeshed
// independently (its own vertex count and connectivity), with Gaussian noise along the normals;
// and, for evaluation, where each of its vertices truly lies on the template.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::synth {

struct ReconstructionOptions {
  double edge_jitter = 0.10;   ///< target edge length varies by ±this fraction per frame
  double noise_sigma = 0.001;  ///< metres of Gaussian noise along the vertex normals
  int iterations = 3;          ///< isotropic remeshing iterations
};

struct Reconstruction {
  core::Mesh mesh;                  ///< V' and F' of the reconstruction (no colours yet)
  std::vector<int> face;            ///< per reconstruction vertex: the template face it lies on
  Eigen::MatrixXd barycentric;      ///< per reconstruction vertex: barycentric coordinates in that face
  double target_edge = 0;           ///< the edge length this frame was remeshed to
};

/// Remeshes `truth` (a closed manifold template surface, V×3 in this frame) with a target edge of
/// `edge` × (1 ± jitter) chosen by `seed`, after a seeded tangential perturbation so no two frames
/// share connectivity; records each output vertex's noise-free closest point on `truth`
/// (face + barycentric), then adds the noise.
Reconstruction reconstruct(const core::Mesh& truth, double edge, std::uint64_t seed,
                           const ReconstructionOptions& options = {});

/// Mean edge length of a mesh.
double mean_edge_length(const core::Mesh& mesh);

/// Points on `surface` given by face + barycentric rows.
Eigen::MatrixXd surface_points(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& face,
                               const Eigen::MatrixXd& barycentric);

}  // namespace surfcap::synth
