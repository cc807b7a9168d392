#pragma once
// Dense targets (casas2011 §3.2's final fit): every template surface vertex towards its compatible
// closest point on the child's reconstruction or, when both meshes have vertex colours, towards the
// colour-weighted mean of the reconstruction vertices near that point (photometric dense fit).
// Neither the template's closing surface nor a vertex whose target is not observed (a hole's rim,
// observed_surface.hpp) gets a target.

#include <Eigen/Core>

#include <memory>
#include <optional>

#include "surfcap/align/target_set.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::geometry {
class VertexGrid;
}

namespace surfcap::align {

class AlignmentTemplate;
class ObservedSurface;
struct PairwiseOptions;
struct PairwiseResult;

/// Photometric dense fit: the colour σ (RGB 0..1; off: geometry only) and the search radius of
/// the colour-weighted target.
struct ColorOptions {
  std::optional<double> sigma = 0.15;
  double radius_edges = 1.5;  ///< template mean edges

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("sigma", self.sigma, "Photometric dense fit: colour sigma (RGB 0..1)", core::Range::above(0));
    t.field("radius_edges", self.radius_edges, "Search radius of the photometric target (template mean edges)",
            core::Range::above(0));
  }
};

class DenseTargets {
 public:
  DenseTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target, const ObservedSurface& observed,
               const Eigen::MatrixXd* target_colors, const PairwiseOptions& options);
  ~DenseTargets();
  DenseTargets(const DenseTargets&) = delete;
  DenseTargets& operator=(const DenseTargets&) = delete;

  /// Sets the dense target of every matched surface vertex; returns how many were matched (and
  /// counts the colour-moved ones in `result.color_constraints`).
  long add(const Eigen::MatrixXd& surface, TargetSet& targets, PairwiseResult& result) const;

 private:
  /// The colour-weighted target near `closest` for template vertex `v`, when there is one.
  std::optional<Eigen::Vector3d> colour_target(long v, const Eigen::Vector3d& closest,
                                               const Eigen::Vector3d& normal) const;

  const AlignmentTemplate& model_;
  const geometry::SurfaceQuery& target_;
  const ObservedSurface& observed_;
  const Eigen::MatrixXd* target_colors_;
  const PairwiseOptions& options_;
  double gate_ = 0, color_radius_ = 0;
  std::unique_ptr<geometry::VertexGrid> grid_;  ///< null: geometry only
};

}  // namespace surfcap::align
