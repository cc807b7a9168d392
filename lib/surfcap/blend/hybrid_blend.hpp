#pragma once
// Hybrid non-linear blend (casas2011 eq. 3, casas2013 §3.1.2):
//   M(t, w) = Σ_j g(w, w_j) (M_L(t, w_j) + D_NL(t, w_j)),  D_NL = M_NL − M_L,
// with g the multilinear interpolation on a tensor grid of reference weights in [0,1]^d. Since
// M_L is linear in the weights this is M_L(t, w) + Σ_j g_j D_NL(t, w_j): a linear blend plus at
// most 2^d sparse, quantised displacement fields. The grid is refined by recursive bisection
// until the hybrid is within ε of the exact blend at every checked point.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surfcap/blend/source_set.hpp"
#include "surfcap/core/progress.hpp"

namespace surfcap::blend {

struct HybridOptions {
  double tolerance_m = 0.005;      ///< ε: max vertex error of the hybrid against the exact blend
  double sparsity_fraction = 0.1;  ///< store a vertex's displacement only where |D| > ε·fraction
  bool quantise = true;            ///< store displacements as float16 (else float32)
  int max_depth = 6;               ///< never split an interval narrower than 2^-max_depth
  /// Checked points per interval and axis: 1 = the midpoint (the paper), 3 = also the quarter
  /// points (safer: the error need not peak at the midpoint).
  int checks_per_interval = 3;
  int threads = 0;  ///< 0: all hardware threads; results do not depend on it
  void validate() const;
};

/// D_NL(t, w_j) of one reference at one frame: the stored vertices and their displacements.
struct SparseDisplacement {
  std::vector<std::int32_t> vertices;
  std::vector<float> values;  ///< 3 per stored vertex, already rounded to the storage precision
};

class HybridBlend {
 public:
  /// Recursive bisection from the corners ({0,1} per axis).
  static HybridBlend build(const SourceSet& sources, const HybridOptions& options,
                           const core::ProgressCallback& progress = {});
  /// Fixed reference grid (e.g. {0, 0.5, 1} = "1 reference"): no bisection.
  static HybridBlend with_breakpoints(const SourceSet& sources, std::vector<std::vector<double>> breakpoints,
                                      const HybridOptions& options);

  /// M(t, u) into `result` (n×3); u ∈ [0,1]^d, clamped.
  void evaluate_into(const SourceSet& sources, int t, const std::vector<double>& u, Eigen::MatrixXd& result) const;
  Eigen::MatrixXd evaluate(const SourceSet& sources, int t, const std::vector<double>& u) const;

  /// max over frames and vertices of |M(t,u) − M_NL(t,u)| (metres).
  double max_error(const SourceSet& sources, const std::vector<double>& u) const;

  int dimensions() const { return static_cast<int>(breakpoints_.size()); }
  const std::vector<std::vector<double>>& breakpoints() const { return breakpoints_; }
  /// Grid nodes in order (axis 0 fastest); corners included (their displacement is zero).
  long node_count() const { return static_cast<long>(node_coordinates_.size()); }
  const std::vector<double>& node_coordinates(long node) const { return node_coordinates_[node]; }
  bool is_corner(long node) const;
  /// References beyond the sources: node_count() − 2^d.
  long reference_count() const { return node_count() - (1L << dimensions()); }
  int frame_count() const { return frame_count_; }
  const SparseDisplacement& displacement(long node, int t) const { return displacements_[node][t]; }
  long stored_vertices() const;
  /// Bytes of the stored fields: per stored vertex an int32 index and 3 values (2 or 4 bytes),
  /// plus an int64 offset per (node, frame).
  long memory_bytes() const;
  /// Largest error found at the checked points of the final grid (metres).
  double checked_max_error() const { return checked_max_error_; }
  long exact_blends() const { return exact_blends_; }
  const HybridOptions& options() const { return options_; }

 private:
  long node_index(const std::vector<long>& grid_index) const;
  void rebuild_nodes(const SourceSet& sources, std::vector<std::vector<SparseDisplacement>> previous,
                     const std::vector<std::vector<double>>& previous_breakpoints);
  SparseDisplacement store(const Eigen::MatrixXd& displacement) const;

  HybridOptions options_;
  int frame_count_ = 0;
  std::vector<std::vector<double>> breakpoints_;
  std::vector<std::vector<double>> node_coordinates_;
  std::vector<std::vector<SparseDisplacement>> displacements_;  // [node][t]
  double checked_max_error_ = 0;
  long exact_blends_ = 0;
};

}  // namespace surfcap::blend
