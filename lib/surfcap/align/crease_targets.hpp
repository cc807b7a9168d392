#pragma once
// Crease targets: where a thin flap flares (a skirt's hem, a sole's rim), the one-sided dense fit
// slides the template round its rim onto the underside; the template's straight convex crease
// vertices at rest are drawn to the closest point of the reconstruction's convex creases
// (creases.hpp), replacing their closest-point target; not to a point on a hole's rim
// (observed_surface.hpp).

#include <Eigen/Core>

#include <memory>
#include <optional>

#include "surfcap/align/target_set.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

class AlignmentTemplate;
class CreaseLines;
class ObservedSurface;
struct PairwiseResult;

/// Template vertices on a convex crease of the rest surface (dihedral angle > `angle_deg`) are
/// drawn to the reconstruction's convex creases within `distance_edges` (bisector within the
/// normal gate), with `weight`. Only straight stretches of the template's creases are matched
/// (straight_crease_vertices: sqrt(λ₂/λ₁) of the crease vertices within `straight_radius_height`
/// ≤ `straightness`; off: every crease vertex). The radius is a body scale (a hand's crease loop
/// is a whole loop within it at any mesh resolution), not a number of edges.
struct CreaseOptions {
  std::optional<double> weight = 0.3;
  double angle_deg = 50;
  double distance_edges = 4;
  std::optional<double> straightness = 0.45;
  double straight_radius_height = 0.048;
  int patch_levels = 2;  ///< crease matching also at the last this many patch levels (always in the dense fit)

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("weight", self.weight, "Weight of crease matching: template rim vertices to the reconstruction's creases",
            Range::above(0));
    t.field("angle_deg", self.angle_deg, "Dihedral angle above which a convex edge is a crease", Range::open(0, 180));
    t.field("distance_edges", self.distance_edges, "Crease matching gate (template mean edges)", Range::above(0));
    t.field("straightness", self.straightness,
            "Match only straight template crease stretches: max sqrt(l2/l1) of nearby crease vertices", Range::above(0));
    t.field("straight_radius_height", self.straight_radius_height,
            "Neighbourhood of the straightness test (fraction of the template height)", Range::above(0));
    t.field("patch_levels", self.patch_levels, "Crease matching also at the last N patch levels", Range::at_least(0));
  }
};

class CreaseTargets {
 public:
  /// `normal_compatibility`: the minimum cosine between a vertex normal and a crease's bisector.
  CreaseTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target, const ObservedSurface& observed,
                const CreaseOptions& options, double normal_compatibility);
  ~CreaseTargets();
  CreaseTargets(const CreaseTargets&) = delete;
  CreaseTargets& operator=(const CreaseTargets&) = delete;
  /// Sets the crease targets of the template's crease vertices at `surface`; counts them in `result`.
  void add(const Eigen::MatrixXd& surface, TargetSet& targets, PairwiseResult& result) const;

 private:
  const AlignmentTemplate& model_;
  const geometry::SurfaceQuery& target_;
  const ObservedSurface& observed_;
  const CreaseOptions& options_;
  double normal_compatibility_;
  std::unique_ptr<CreaseLines> lines_;  ///< null: off, or no crease vertex on the template
};

}  // namespace surfcap::align
