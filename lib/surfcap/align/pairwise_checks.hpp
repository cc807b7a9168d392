#pragma once
// What an aligned pair is checked for, and when an edge of the tree has failed. The residual
// (aligned template → reconstruction) is one-sided; two failures it cannot see are checked too: a
// reconstruction left uncovered (a limb collapsed onto another leaves the other one uncovered;
// with cameras, only where they show it: silhouette_evidence.hpp)
// and a template stacked onto itself (a hand pushed up its forearm lies on the forearm's stretch
// of the reconstruction with a normal residual).

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"
#include "surfcap/render/camera.hpp"

namespace surfcap::align {

struct PairwiseResult;

struct PairwiseCheckOptions {
  /// A reconstruction vertex farther than this from the aligned template (mean edges) is uncovered;
  /// with cameras, only when some camera sees it as far beyond the template's silhouette.
  double uncovered_distance_edges = 1.5;
  /// Stacked layers: two aligned template vertices closer than `stacked_distance_edges`, facing
  /// the same way (normals' cosine above 0.5), that lie more than `stacked_rest_distance_height`
  /// apart at rest.
  double stacked_distance_edges = 0.5;
  double stacked_rest_distance_height = 0.057;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("uncovered_distance_edges", self.uncovered_distance_edges,
            "A reconstruction vertex farther than this from the aligned template (and, with cameras, beyond its "
            "silhouette) is uncovered (mean edges)",
            Range::above(0));
    t.field("stacked_distance_edges", self.stacked_distance_edges,
            "Aligned template vertices closer than this may be stacked layers (mean edges)", Range::above(0));
    t.field("stacked_rest_distance_height", self.stacked_rest_distance_height,
            "... when farther apart than this at rest (fraction of the template height)", Range::above(0));
  }
};

/// When an aligned child has failed: a mean residual above `failure_residual_mm`, more than
/// `max_uncovered` of its reconstruction's vertices uncovered or more than `max_stacked` of the
/// template's in stacked layers. One whose mean residual grew beyond `residual_growth` × its
/// parent's (not from the root) has not failed but is worth a retry.
struct FailureOptions {
  double failure_residual_mm = 4;
  double max_uncovered = 0.01;
  double max_stacked = 0.005;
  std::optional<double> residual_growth = 1.3;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("failure_residual_mm", self.failure_residual_mm,
            "Mean residual above which a frame is re-aligned from its next most similar aligned frame", Range::above(0));
    t.field("max_uncovered", self.max_uncovered,
            "Fraction of a reconstruction left uncovered by the aligned template above which a frame failed",
            Range::closed(0, 1));
    t.field("max_stacked", self.max_stacked,
            "Fraction of the template's vertices in stacked layers above which a frame failed", Range::above_to(0, 1));
    t.field("residual_growth", self.residual_growth,
            "A frame whose mean residual exceeds this many times its parent's is retried", Range::above(0));
  }
};

/// Per surface vertex of `surface` (n×3 template connectivity): distance to the target surface.
Eigen::VectorXd surface_distances(const Eigen::MatrixXd& surface, const geometry::SurfaceQuery& target);

/// Fraction of the target's vertices farther than `gate` from the surface (`aligned`, `F`): the
/// posed template. With `counted` (per target vertex), of the counted vertices only. With
/// `cameras` (not empty), a far vertex is uncovered only where some camera sees it outside the
/// posed template's silhouette (silhouette_evidence.hpp): phantom volume of a visual hull is not.
double uncovered_fraction(const geometry::SurfaceQuery& target, const Eigen::MatrixXd& aligned,
                          const Eigen::MatrixXi& F, double gate, const std::vector<char>* counted = nullptr,
                          const std::vector<render::Camera>* cameras = nullptr);

/// The rows of `points` with no row of `V` within `gate` (ascending): the only points whose
/// closest point on a surface with vertices `V` can lie farther than `gate` (a surface is never
/// farther than its nearest vertex). The rest lie within `gate` of the surface for certain, with
/// a relative margin of 1e-9 for the rounding of the closest-point computation.
std::vector<long> far_from_vertices(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V, double gate);

/// Fraction of the vertices of `aligned` (the template surface posed, faces F) in stacked layers:
/// within `distance` of another vertex with a normal at less than 60° from theirs that lies more
/// than `rest_distance` from them in `rest`. Two parts that touch face each other and do not count.
double stacked_fraction(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                        double distance, double rest_distance);
/// The same per vertex: 1 for a vertex in a stacked layer.
std::vector<char> stacked_vertices(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                                   double distance, double rest_distance);

/// Merged regions of an aligned pair: where two parts of the template that lie far apart at rest
/// (more than kRestDistanceHeight of its height `height`) face each other within kDistanceEdges of
/// its mean edge `mean_edge` and the reconstruction `target` shows no surface between them — the
/// point halfway lies farther from it than the two lie from each other, and farther than one mean
/// edge: a reconstruction that fused them (legs joined by a visual hull's phantom volume, an arm
/// fused to the torso). Two free parts close together keep the reconstruction's surfaces between
/// them and do not count. `merged` is 1 per vertex of `aligned` (the template surface posed, faces
/// F; `rest` at rest) in a merged region; `regions` counts its connected pieces of at least
/// kMinimumRegion vertices (smaller ones are not kept).
struct MergedRegions {
  static constexpr double kDistanceEdges = 2.0;
  static constexpr double kRestDistanceHeight = 0.057;
  static constexpr long kMinimumRegion = 4;
  std::vector<char> merged;
  long regions = 0;
  double fraction = 0;  ///< of the vertices of `aligned`
};
MergedRegions merged_regions(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                             const geometry::SurfaceQuery& target, double mean_edge, double height);

/// An attempt passes, fits clearly worse than its parent did (`grown`: worth a retry, but no
/// evidence of a wrong alignment on its own) or failed.
enum class Verdict { pass, grown, failed };

/// The verdict on an aligned pair whose parent had mean residual `parent_residual` (0: no
/// reference, as for the root's children), and in words why it did not pass.
Verdict verdict(const PairwiseResult& result, double parent_residual, const FailureOptions& options);
std::string failure_reason(const PairwiseResult& result, double parent_residual, const FailureOptions& options);

}  // namespace surfcap::align
