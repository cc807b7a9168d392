#include "surfcap/blend/hybrid_blend.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::blend {
namespace {

std::vector<double> check_fractions(int checks) {
  return checks == 1 ? std::vector<double>{0.5} : std::vector<double>{0.25, 0.5, 0.75};
}

struct CheckPoint {
  std::vector<double> u;
  std::vector<std::pair<int, std::size_t>> split;  // (axis, interval) to bisect when it fails
};

}  // namespace

void HybridOptions::validate() const {
  if (!(tolerance_m > 0)) throw core::bad_arguments("hybrid tolerance must be positive");
  if (!(sparsity_fraction >= 0 && sparsity_fraction < 1))
    throw core::bad_arguments("hybrid sparsity fraction must be in [0, 1)");
  if (max_depth < 0 || max_depth > 20) throw core::bad_arguments("hybrid max depth must be in 0..20");
  if (checks_per_interval != 1 && checks_per_interval != 3)
    throw core::bad_arguments("hybrid checks per interval must be 1 or 3");
}

bool HybridBlend::is_corner(long node) const {
  for (double c : node_coordinates_[node])
    if (c != 0.0 && c != 1.0) return false;
  return true;
}

long HybridBlend::node_index(const std::vector<long>& grid_index) const {
  long index = 0, stride = 1;
  for (std::size_t a = 0; a < breakpoints_.size(); ++a) {
    index += grid_index[a] * stride;
    stride *= static_cast<long>(breakpoints_[a].size());
  }
  return index;
}

SparseDisplacement HybridBlend::store(const Eigen::MatrixXd& displacement) const {
  SparseDisplacement stored;
  const double threshold = options_.tolerance_m * options_.sparsity_fraction;
  for (long v = 0; v < displacement.rows(); ++v) {
    if (!(displacement.row(v).norm() > threshold)) continue;
    stored.vertices.push_back(static_cast<std::int32_t>(v));
    for (int c = 0; c < 3; ++c) {
      const auto value = static_cast<float>(displacement(v, c));
      stored.values.push_back(options_.quantise ? core::half_to_float(core::float_to_half(value)) : value);
    }
  }
  return stored;
}

void HybridBlend::rebuild_nodes(const SourceSet& sources, std::vector<std::vector<SparseDisplacement>> previous,
                                const std::vector<std::vector<double>>& previous_coordinates_list) {
  std::map<std::vector<double>, std::size_t> previous_nodes;
  for (std::size_t i = 0; i < previous_coordinates_list.size(); ++i) previous_nodes[previous_coordinates_list[i]] = i;
  long total = 1;
  for (const auto& axis : breakpoints_) total *= static_cast<long>(axis.size());
  node_coordinates_.assign(static_cast<std::size_t>(total), {});
  displacements_.assign(static_cast<std::size_t>(total), std::vector<SparseDisplacement>(frame_count_));
  std::vector<long> fresh;
  for (long node = 0; node < total; ++node) {
    long rest = node;
    std::vector<double> u(breakpoints_.size());
    for (std::size_t a = 0; a < breakpoints_.size(); ++a) {
      const long size = static_cast<long>(breakpoints_[a].size());
      u[a] = breakpoints_[a][rest % size];
      rest /= size;
    }
    node_coordinates_[node] = u;
    if (auto found = previous_nodes.find(u); found != previous_nodes.end())
      displacements_[node] = std::move(previous[found->second]);
    else if (!is_corner(node))
      fresh.push_back(node);
  }
  // D_NL(t, w_j) = M_NL − M_L for every new reference and frame (casas2011 §4.1).
  const long jobs = static_cast<long>(fresh.size()) * frame_count_;
  core::parallel_for(jobs, options_.threads, [&](long job) {
    const long node = fresh[job / frame_count_];
    const int t = static_cast<int>(job % frame_count_);
    const auto& u = node_coordinates_[node];
    displacements_[node][t] = store(sources.exact(t, u) - sources.linear(t, u));
  });
  exact_blends_ += jobs;
}

HybridBlend HybridBlend::with_breakpoints(const SourceSet& sources, std::vector<std::vector<double>> breakpoints,
                                          const HybridOptions& options) {
  options.validate();
  if (static_cast<int>(breakpoints.size()) != sources.dimensions())
    throw core::bad_arguments("hybrid breakpoints: one list per weight-space axis");
  HybridBlend hybrid;
  hybrid.options_ = options;
  hybrid.frame_count_ = sources.frame_count();
  for (auto& axis : breakpoints) {
    axis.push_back(0.0);
    axis.push_back(1.0);
    std::sort(axis.begin(), axis.end());
    axis.erase(std::unique(axis.begin(), axis.end()), axis.end());
    if (axis.front() < 0 || axis.back() > 1) throw core::bad_arguments("hybrid breakpoints must lie in [0, 1]");
  }
  hybrid.breakpoints_ = std::move(breakpoints);
  hybrid.rebuild_nodes(sources, {}, {});
  return hybrid;
}

HybridBlend HybridBlend::build(const SourceSet& sources, const HybridOptions& options,
                               const core::ProgressCallback& progress) {
  HybridBlend hybrid =
      with_breakpoints(sources, std::vector<std::vector<double>>(static_cast<std::size_t>(sources.dimensions())), options);
  const std::vector<double> fractions = check_fractions(options.checks_per_interval);
  const double min_width = std::ldexp(1.0, -options.max_depth);
  const int d = hybrid.dimensions();
  for (;;) {
    // Check points: the local lattice {0, fractions, 1}^d of every cell minus its corners.
    std::vector<double> local{0.0};
    local.insert(local.end(), fractions.begin(), fractions.end());
    local.push_back(1.0);
    std::map<std::vector<double>, CheckPoint> points;
    std::vector<std::size_t> cell(static_cast<std::size_t>(d), 0);
    for (bool more_cells = true; more_cells;) {
      std::vector<std::size_t> pick(static_cast<std::size_t>(d), 0);
      for (bool more_points = true; more_points;) {
        CheckPoint point;
        point.u.resize(static_cast<std::size_t>(d));
        for (int a = 0; a < d; ++a) {
          const auto& axis = hybrid.breakpoints_[a];
          const double f = local[pick[a]], lo = axis[cell[a]], hi = axis[cell[a] + 1];
          point.u[a] = f == 1.0 ? hi : lo + f * (hi - lo);
          if (f != 0.0 && f != 1.0 && (hi - lo) * 0.5 >= min_width) point.split.emplace_back(a, cell[a]);
        }
        const bool on_corner = std::all_of(pick.begin(), pick.end(),
                                           [&](std::size_t p) { return p == 0 || p + 1 == local.size(); });
        if (!on_corner) points.emplace(point.u, point);
        more_points = false;
        for (int a = 0; a < d && !more_points; ++a)
          if (++pick[a] < local.size()) more_points = true; else pick[a] = 0;
      }
      more_cells = false;
      for (int a = 0; a < d && !more_cells; ++a)
        if (++cell[a] + 1 < hybrid.breakpoints_[a].size()) more_cells = true; else cell[a] = 0;
    }
    std::vector<const CheckPoint*> ordered;
    for (const auto& entry : points) ordered.push_back(&entry.second);
    std::vector<double> errors(ordered.size());
    for (std::size_t p = 0; p < ordered.size(); ++p) {
      errors[p] = hybrid.max_error(sources, ordered[p]->u);
      if (progress) progress(p + 1, ordered.size());
    }
    hybrid.exact_blends_ += static_cast<long>(ordered.size()) * hybrid.frame_count_;
    double worst = 0;
    std::vector<std::vector<double>> midpoints(static_cast<std::size_t>(d));
    for (std::size_t p = 0; p < ordered.size(); ++p) {
      worst = std::max(worst, errors[p]);
      if (errors[p] <= options.tolerance_m) continue;
      for (const auto& [axis, interval] : ordered[p]->split) {
        const auto& breaks = hybrid.breakpoints_[axis];
        midpoints[axis].push_back(0.5 * (breaks[interval] + breaks[interval + 1]));
      }
    }
    hybrid.checked_max_error_ = worst;
    if (std::all_of(midpoints.begin(), midpoints.end(), [](const auto& m) { return m.empty(); })) break;
    const auto previous_coordinates = hybrid.node_coordinates_;
    auto previous_displacements = std::move(hybrid.displacements_);
    for (int a = 0; a < d; ++a) {
      auto& axis = hybrid.breakpoints_[a];
      axis.insert(axis.end(), midpoints[a].begin(), midpoints[a].end());
      std::sort(axis.begin(), axis.end());
      axis.erase(std::unique(axis.begin(), axis.end()), axis.end());
    }
    hybrid.rebuild_nodes(sources, std::move(previous_displacements), previous_coordinates);
  }
  return hybrid;
}

void HybridBlend::evaluate_into(const SourceSet& sources, int t, const std::vector<double>& u,
                                Eigen::MatrixXd& result) const {
  const int d = dimensions();
  std::vector<double> clamped(u.begin(), u.end());
  for (double& c : clamped) c = std::clamp(c, 0.0, 1.0);
  sources.linear_into(t, clamped, result);
  // g(w, w_j): multilinear weights of the 2^d nodes of the grid cell holding u.
  long base[8];
  double fraction[8];
  long strides[8];
  long stride = 1;
  for (int a = 0; a < d; ++a) {
    const auto& axis = breakpoints_[a];
    const auto upper = std::upper_bound(axis.begin() + 1, axis.end() - 1, clamped[a]);
    base[a] = static_cast<long>(upper - axis.begin()) - 1;
    fraction[a] = (clamped[a] - axis[base[a]]) / (axis[base[a] + 1] - axis[base[a]]);
    strides[a] = stride;
    stride *= static_cast<long>(axis.size());
  }
  for (int corner = 0; corner < (1 << d); ++corner) {
    double g = 1;
    long node = 0;
    for (int a = 0; a < d; ++a) {
      const bool upper = (corner >> a) & 1;
      g *= upper ? fraction[a] : 1.0 - fraction[a];
      node += (base[a] + (upper ? 1 : 0)) * strides[a];
    }
    if (g == 0) continue;
    const SparseDisplacement& field = displacements_[node][t];
    const float* values = field.values.data();
    for (std::size_t k = 0; k < field.vertices.size(); ++k, values += 3) {
      const long v = field.vertices[k];
      result(v, 0) += g * values[0];
      result(v, 1) += g * values[1];
      result(v, 2) += g * values[2];
    }
  }
}

Eigen::MatrixXd HybridBlend::evaluate(const SourceSet& sources, int t, const std::vector<double>& u) const {
  Eigen::MatrixXd result;
  evaluate_into(sources, t, u, result);
  return result;
}

double HybridBlend::max_error(const SourceSet& sources, const std::vector<double>& u) const {
  std::vector<double> per_frame(static_cast<std::size_t>(frame_count_), 0.0);
  core::parallel_for(frame_count_, options_.threads, [&](long t) {
    const Eigen::MatrixXd difference = evaluate(sources, static_cast<int>(t), u) - sources.exact(static_cast<int>(t), u);
    per_frame[static_cast<std::size_t>(t)] = difference.rowwise().norm().maxCoeff();
  });
  return *std::max_element(per_frame.begin(), per_frame.end());
}

long HybridBlend::stored_vertices() const {
  long count = 0;
  for (const auto& node : displacements_)
    for (const auto& frame : node) count += static_cast<long>(frame.vertices.size());
  return count;
}

long HybridBlend::memory_bytes() const {
  const long value_bytes = options_.quantise ? 2 : 4;
  return stored_vertices() * (4 + 3 * value_bytes) + node_count() * frame_count_ * 8 + 8;
}

}  // namespace surfcap::blend
