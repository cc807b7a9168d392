#pragma once
// The synthetic actor's body: an implicit surface (smooth union of round cones around the
// skeleton's bones, plus a flared skirt) meshed into a closed, manifold, genus-0 template with
// CGAL's surface mesher and isotropic remeshing; skinning weights, garment weights and body
// regions per vertex.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/synth/skeleton.hpp"

namespace surfcap::synth {

/// What the surface is made of, for the texture.
enum class Region : int { skin = 0, hair = 1, shirt = 2, skirt = 3, trousers = 4, shoes = 5 };

struct SkirtShape {
  double waist_height = 1.02;   ///< metres (for a 1.75 m actor; scales with height)
  double waist_radius = 0.155;
  double hem_height = 0.70;
  double hem_radius = 0.25;
  double depth_scale = 0.80;    ///< front-back / left-right radius ratio
};

struct BodyOptions {
  double height = 1.75;
  int target_vertices = 3000;   ///< template vertex count (±5%)
  SkirtShape skirt;
  int seed = 1;                 ///< CGAL's surface mesher samples its initial points at random
};

/// A signed-distance-like field of the rest-pose body: negative inside (metres, approximately).
class BodyField {
 public:
  BodyField(const Skeleton& skeleton, const SkirtShape& skirt);
  double operator()(const Eigen::Vector3d& p) const;
  /// Bounding sphere of the body.
  Eigen::Vector3d centre() const { return centre_; }
  double radius() const { return radius_; }

 private:
  struct RoundCone {
    Eigen::Vector3d a, b;
    double ra, rb;
    double depth_scale;  ///< scales z before measuring distance (flattened torso)
  };
  double cone_distance(const RoundCone& cone, const Eigen::Vector3d& p) const;
  std::vector<RoundCone> cones_;
  SkirtShape skirt_;  ///< scaled to the actor's height
  Eigen::Vector3d centre_;
  double radius_;
};

struct Body {
  Skeleton skeleton;
  SkirtShape skirt;
  core::Mesh rest;                 ///< rest-pose template (closed, manifold, genus 0)
  Eigen::MatrixXd skin_weights;    ///< V×J linear-blend skinning weights (rows sum to 1)
  Eigen::VectorXd garment_weight;  ///< V, 1 on the skirt, 0 elsewhere, smooth in between
  Eigen::VectorXd garment_depth;   ///< V, 0 at the waist → 1 at the hem (where garment_weight > 0)
  std::vector<Region> regions;     ///< per vertex
};

/// Builds the body (deterministic for a given options.seed).
Body make_body(const BodyOptions& options);

/// Meshes `field` (closed manifold surface), then remeshes isotropically towards
/// `target_vertices`. Exposed for tests.
core::Mesh mesh_implicit_surface(const BodyField& field, int target_vertices, int seed);

}  // namespace surfcap::synth
