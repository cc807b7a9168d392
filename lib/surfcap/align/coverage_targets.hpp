#pragma once
// Coverage pulls (child → template correspondences): the dense fit is one-sided (template →
// reconstruction), so a limb left behind or laid onto another limb fits with a small residual.
// Every reconstruction vertex farther than the uncovered gate from the aligned template (but
// within reach) pulls its closest template point towards itself; a reconstruction vertex on a
// hole's rim (observed_surface.hpp) pulls nothing, nor is the template's closing surface pulled.
// With the capture's cameras, only a vertex some camera sees outside the aligned template's
// silhouette pulls (silhouette_evidence.hpp): a visual hull's phantom volume does not.

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "surfcap/align/target_set.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"
#include "surfcap/render/camera.hpp"

namespace surfcap::align {

class AlignmentTemplate;
class ObservedSurface;
struct PairwiseOptions;
struct PairwiseResult;

/// The weight of each pull (off: no pulls).
struct CoverageOptions {
  std::optional<double> weight = 0.9;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("weight", self.weight, "Weight of the coverage (reconstruction to template) pulls", core::Range::above(0));
  }
};

class CoverageTargets {
 public:
  /// `cameras` (may be null or empty: every far vertex pulls) must outlive the targets.
  CoverageTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target, const ObservedSurface& observed,
                  const PairwiseOptions& options, const std::vector<render::Camera>* cameras);
  /// Adds the pulls of the reconstruction vertices uncovered by `surface` within `reach` (m),
  /// merged with the targets there (feature_constraints.hpp); counts them in `result`.
  void add(const Eigen::MatrixXd& surface, double reach, TargetSet& targets, PairwiseResult& result) const;

 private:
  const AlignmentTemplate& model_;
  const geometry::SurfaceQuery& target_;
  const ObservedSurface& observed_;
  const PairwiseOptions& options_;
  const std::vector<render::Camera>* cameras_;
  Eigen::MatrixXd target_normals_;
};

}  // namespace surfcap::align
