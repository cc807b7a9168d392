#pragma once
// What a studio's reconstruction of one frame looks like: the true surface remeshed
// independently (its own vertex count and connectivity), with Gaussian noise along the normals;
// and, for evaluation, where each of its vertices truly lies on the template.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "surfcap/core/mesh.hpp"

namespace surfcap::synth {

/// What happens to the faces fewer than `min_views` cameras see.
enum class UnseenMode { keep, remove, rough };

/// Per reconstruction vertex: how its ground-truth point relates to it (ground_truth/…status.npy).
enum class VertexStatus : std::uint8_t {
  on_surface = 0,  ///< within the noise of its true surface point
  phantom = 1,     ///< visual-hull volume off the true surface; the truth is the nearest true point
  outlier = 2,     ///< pushed off the surface along the normal
  blob = 3,        ///< part of a spurious blob near the body
  rough = 4,       ///< on a patch no two cameras saw, noisier than the rest
};

struct ReconstructionOptions {
  double edge_jitter = 0.10;   ///< target edge length varies by ±this fraction per frame
  double noise_sigma = 0.001;  ///< metres of Gaussian noise along the vertex normals
  int iterations = 3;          ///< isotropic remeshing iterations
  // Studio models (docs/synth.md), all off by default.
  bool visual_hull = false;        ///< shape from silhouette instead of a remesh of the true surface
  double voxel = 0.01;             ///< carving grid spacing, metres
  double surface_tolerance = 0.004;  ///< hull vertices this close to the true surface are put on it
  int vertices = 0;                ///< target vertex count (0: the template's mean edge length)
  bool floor_cut = false;          ///< faces below floor_height removed (open soles)
  double floor_height = 0.02;
  UnseenMode unseen = UnseenMode::keep;
  int min_views = 2;               ///< cameras that must see a face for it to count as seen
  double rough_sigma = 0.004;      ///< extra noise on unseen patches (UnseenMode::rough), metres
  double outlier_fraction = 0;     ///< share of the vertices pushed off the surface
  double outlier_distance = 0.02;  ///< their mean offset along the normal, metres
  double blobs = 0;                ///< mean number of spurious blobs per frame
  double blob_radius = 0.012;      ///< their mean radius, metres
  bool textures = false;           ///< each frame also as OBJ + MTL + PNG atlas baked from the cameras
  double texture_scale = 2;        ///< atlas texels per camera pixel
  /// Any model beyond remeshing + noise is on (the capture then has status files).
  bool studio() const {
    return visual_hull || floor_cut || unseen != UnseenMode::keep || outlier_fraction > 0 || blobs > 0 || textures;
  }
};

struct Reconstruction {
  core::Mesh mesh;                  ///< V' and F' of the reconstruction (no colours yet)
  std::vector<int> face;            ///< per reconstruction vertex: the template face it lies on
  Eigen::MatrixXd barycentric;      ///< per reconstruction vertex: barycentric coordinates in that face
  double target_edge = 0;           ///< the edge length this frame was remeshed to
  std::vector<std::uint8_t> status; ///< per vertex: a VertexStatus (studio models only)
};

/// Remeshes `truth` (a closed manifold template surface, V×3 in this frame) with a target edge of
/// `edge` × (1 ± jitter) chosen by `seed`, after a seeded tangential perturbation so no two frames
/// share connectivity; records each output vertex's noise-free closest point on `truth`
/// (face + barycentric), then adds the noise.
Reconstruction reconstruct(const core::Mesh& truth, double edge, std::uint64_t seed,
                           const ReconstructionOptions& options = {});

/// The remeshing step of `reconstruct` alone: `truth` perturbed tangentially and remeshed to
/// edge × (1 ± jitter) (written to `target_edge`), from the engine seeded with `seed`.
core::Mesh remesh_truth(const core::Mesh& truth, double edge, std::uint64_t seed, const ReconstructionOptions& options,
                        double& target_edge);

/// CGAL isotropic remeshing of a closed or open, edge-manifold mesh of any number of components.
core::Mesh remesh_surface(const core::Mesh& mesh, double edge, int iterations);

/// Each row of `points`' closest point on `truth` (face + clamped barycentric coordinates).
void closest_truth_points(const core::Mesh& truth, const Eigen::MatrixXd& points, std::vector<int>& face,
                          Eigen::MatrixXd& barycentric);

/// Standard normal and uniform numbers from a 64-bit Mersenne Twister (Box–Muller): the same on
/// every platform, unlike the standard library's distributions.
struct Gaussian {
  std::mt19937_64 engine;
  double uniform() { return static_cast<double>(engine() >> 11) * (1.0 / 9007199254740992.0); }
  double next() {
    const double u1 = (static_cast<double>(engine() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    const double u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }
};

/// Mean edge length of a mesh.
double mean_edge_length(const core::Mesh& mesh);

/// Points on `surface` given by face + barycentric rows.
Eigen::MatrixXd surface_points(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& face,
                               const Eigen::MatrixXd& barycentric);

}  // namespace surfcap::synth
