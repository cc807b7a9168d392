#pragma once
// Independent remeshing of a surface (CGAL isotropic remeshing): turns a mesh sequence with one
// connectivity into an "unstructured capture" (a new vertex count and connectivity every frame),
// keeping each new vertex's location on the source mesh (face + barycentric) as ground truth.
// Also used to clean/remesh a template to a target vertex count.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::synth {

struct RemeshOptions {
  double edge = 0.02;            ///< target edge length (m)
  double edge_jitter = 0.1;      ///< the edge varies by ±this fraction with the seed
  double tangential_jitter = 0.3; ///< seeded tangential perturbation before remeshing, in edges
  double noise_sigma = 0;        ///< Gaussian noise along the normals after remeshing (m)
  int iterations = 3;
  std::uint64_t seed = 1;
};

struct RemeshResult {
  core::Mesh mesh;
  std::vector<int> face;        ///< per new vertex: the source face under it (before noise)
  Eigen::MatrixXd barycentric;  ///< per new vertex: its barycentric coordinates in that face
};

/// Remeshes a closed manifold surface; deterministic for a seed. internal_error if the source is
/// not manifold.
RemeshResult remesh(const core::Mesh& source, const RemeshOptions& options);

}  // namespace surfcap::synth
