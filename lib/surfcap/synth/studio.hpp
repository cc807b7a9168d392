#pragma once
// A studio's reconstruction of one frame with the artefacts real ones have (docs/synth.md):
// shape from silhouette (merged limbs, phantom volume, lost concavities, changing genus), the
// floor cut (open soles), unseen patches removed or rough, noise with outlier vertices and
// spurious blobs; and the measures of those artefacts against the ground truth.

#include <cstdint>
#include <numeric>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/synth/reconstruction.hpp"
#include "surfcap/synth/visual_hull.hpp"

namespace surfcap::synth {

/// Disjoint sets of 0..n−1: unite(a, b) links a's root under b's.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int i) {
    while (parent_[static_cast<std::size_t>(i)] != i)
      i = parent_[static_cast<std::size_t>(i)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(i)])];
    return i;
  }
  void unite(int a, int b) { parent_[static_cast<std::size_t>(find(a))] = find(b); }

 private:
  std::vector<int> parent_;
};

/// Per face of a mesh: how many cameras see it (front-facing, in the image, not occluded by the
/// mesh itself) and the one that sees it most frontally (−1 when none; then the most frontal one
/// if the face is front-facing to any, else −1).
struct FaceVisibility {
  std::vector<int> views;
  std::vector<int> best_camera;
};
FaceVisibility face_visibility(const core::Mesh& mesh, const std::vector<render::Camera>& cameras);

/// The studio reconstruction of `truth` (a closed manifold surface, this frame's positions) seen
/// by `cameras` with `silhouettes` of the true surface (computed when empty): the models on in
/// `options`, then noise. `edge` is the template's mean edge (used when options.vertices is 0).
/// Ground truth per vertex: the closest true point (face + barycentric) and a VertexStatus.
Reconstruction reconstruct_studio(const core::Mesh& truth, const std::vector<render::Camera>& cameras,
                                  std::vector<Silhouette> silhouettes, double edge, std::uint64_t seed,
                                  const ReconstructionOptions& options);

/// The edge length that gives about `vertices` vertices on a surface of `area` m².
double edge_for_vertices(double area, int vertices);
double surface_area(const core::Mesh& mesh);

/// Body parts for merged-limb detection (per template vertex: its dominant bone's limb, or the skirt).
enum class BodyPart : int { torso = 0, arm_l = 1, arm_r = 2, leg_l = 3, leg_r = 4, garment = 5 };

/// What one frame's reconstruction shows.
struct FrameArtefacts {
  long vertices = 0, faces = 0;
  long components = 0;     ///< connected components, blobs excluded
  long blob_components = 0;
  long holes = 0;          ///< boundary loops
  long genus = 0;          ///< sum over the non-blob components
  long merged_edges = 0;   ///< edges joining body parts that are apart on the true surface
  long phantom = 0, outliers = 0, blob_vertices = 0, rough = 0;  ///< vertices by status
  std::vector<std::uint8_t> merged_vertex;  ///< per vertex: 1 on a merged edge
  std::vector<std::uint8_t> boundary_vertex;  ///< per vertex: 1 on a hole's border
};

/// Topology and artefacts of `mesh`. `rest_points` (n×3, the true points in the rest pose) and
/// `parts` (per vertex: a body part, −1 for none) locate merged limbs: an edge whose ends lie
/// on different parts (not a garment and a leg) more than max(5 cm, 4 × the edge) apart in the
/// rest pose joins what the true surface keeps apart. Empty: no merge detection.
FrameArtefacts measure_artefacts(const core::Mesh& mesh, const std::vector<std::uint8_t>& status,
                                 const Eigen::MatrixXd& rest_points, const std::vector<int>& parts);

}  // namespace surfcap::synth
