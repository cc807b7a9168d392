#include "surfcap/runtime/transition_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "surfcap/core/error.hpp"

namespace surfcap::runtime {

void PlannerOptions::validate() const {
  if (depth < 0 || depth > 100) throw core::bad_arguments("trellis depth must be in [0, 100]");
  if (!(latency_weight >= 0)) throw core::bad_arguments("latency weight λ must be ≥ 0");
  if (!(parameter_step > 0 && parameter_step <= 1)) throw core::bad_arguments("parameter step must be in (0, 1]");
  if (!(similarity_scale > 0)) throw core::bad_arguments("similarity scale must be positive");
  if (!(fps > 0)) throw core::bad_arguments("fps must be positive");
}

TransitionPlanner::TransitionPlanner(const SpaceEvaluator& from, const SpaceEvaluator& to,
                                     const asset::CharacterTransition& similarity, const PlannerOptions& options)
    : from_(&from), to_(&to), similarity_(&similarity), options_(options) {
  options_.validate();
  if (similarity.rows != from.space().node_count() * from.frames() ||
      similarity.cols != to.space().node_count() * to.frames() ||
      similarity.similarity.size() != static_cast<std::size_t>(similarity.rows * similarity.cols))
    throw core::bad_input("transition " + similarity.from + " → " + similarity.to,
                          "similarity matrix does not match the spaces' nodes × frames");
  max_similarity_ = similarity.similarity.empty()
                        ? 1.0
                        : *std::max_element(similarity.similarity.begin(), similarity.similarity.end());
  row_max_.assign(static_cast<std::size_t>(similarity.rows), 0.0f);
  col_max_.assign(static_cast<std::size_t>(similarity.cols), 0.0f);
  for (long i = 0; i < similarity.rows; ++i)
    for (long j = 0; j < similarity.cols; ++j) {
      const float value = similarity.at(i, j);
      row_max_[i] = std::max(row_max_[i], value);
      col_max_[j] = std::max(col_max_[j], value);
    }
}

void TransitionPlanner::build_side(const SpaceEvaluator& space, const MotionState& state, bool forward,
                                   const std::vector<float>& best_of_entry, Side& side) const {
  const int d = space.dimensions(), T = space.frames();
  double u[3];
  space.weight_coordinates(state.parameters.data(), u);
  side.step = space.frames_per_step(u, options_.fps);
  side.levels = 0;
  for (int k = 0; k <= options_.depth; ++k) {
    const double f = state.frame + (forward ? k : -k) * side.step;
    if (!space.cyclic() && (f < -1e-9 || f > T - 1 + 1e-9)) break;
    side.levels = k + 1;
  }
  // Parameter values reachable per axis, with the level at which each is first reachable.
  for (int a = 0; a < d; ++a) {
    const double low = space.parameter_min(a), high = space.parameter_max(a);
    const double delta = options_.parameter_step * (high - low);
    std::vector<double>& values = axis_values_[a];
    std::vector<int>& depths = axis_depths_[a];
    values.assign(1, std::clamp(state.parameters[a], low, high));
    depths.assign(1, 0);
    for (int sign : {-1, 1})
      for (int j = 1; j <= options_.depth && delta > 0; ++j) {
        const double value = std::clamp(state.parameters[a] + sign * j * delta, low, high);
        if (std::abs(value - values[sign < 0 ? 0 : values.size() - 1]) < 1e-12 * (1 + std::abs(value))) break;
        if (sign < 0) {
          values.insert(values.begin(), value);
          depths.insert(depths.begin(), j);
        } else {
          values.push_back(value);
          depths.push_back(j);
        }
      }
  }
  // Parameter combinations (Chebyshev reachability) with their grid cells.
  std::vector<Node>& combos = combos_;
  combos.clear();
  int counts[3] = {1, 1, 1};
  for (int a = 0; a < d; ++a) counts[a] = static_cast<int>(axis_values_[a].size());
  for (int i = 0; i < counts[0]; ++i)
    for (int j = 0; j < counts[1]; ++j)
      for (int k = 0; k < counts[2]; ++k) {
        const int choice[3] = {i, j, k};
        Node node;
        for (int a = 0; a < d; ++a) {
          node.parameters[a] = axis_values_[a][choice[a]];
          node.depth = std::max(node.depth, axis_depths_[a][choice[a]]);
        }
        if (node.depth >= side.levels) continue;
        space.weight_coordinates(node.parameters, u);
        node.entries = space.cell_weights(u, node.index, node.weight);
        combos.push_back(node);
      }
  side.nodes.clear();
  side.depth_start.assign(static_cast<std::size_t>(side.levels + 1), 0);
  for (int level = 0; level < side.levels; ++level) {
    side.depth_start[level] = static_cast<int>(side.nodes.size());
    const double f = space.wrap(state.frame + (forward ? level : -level) * side.step);
    int key = static_cast<int>(std::lround(f));
    key = space.cyclic() ? key % T : std::min(key, T - 1);
    for (const Node& combo : combos) {
      if (combo.depth > level) continue;
      Node node = combo;
      node.depth = level;
      node.bound = 0;
      for (int e = 0; e < node.entries; ++e) {
        node.index[e] = node.index[e] * T + key;
        node.bound += node.weight[e] * best_of_entry[node.index[e]];
      }
      side.nodes.push_back(node);
    }
  }
  side.depth_start[side.levels] = static_cast<int>(side.nodes.size());
}

TransitionPlan TransitionPlanner::search(const MotionState& source, const MotionState& target, int& best_a,
                                         int& best_b) const {
  build_side(*from_, source, true, row_max_, source_side_);
  build_side(*to_, target, false, col_max_, target_side_);
  const Side& s = source_side_;
  const Side& t = target_side_;
  const float* matrix = similarity_->similarity.data();
  const long cols = similarity_->cols;
  const double scale = options_.similarity_scale, lambda = options_.latency_weight;
  const double floor_cost = scale * (1.0 - max_similarity_);
  TransitionPlan plan;
  double best = std::numeric_limits<double>::infinity();
  best_a = best_b = -1;
  // Dijkstra order: every path with latency L costs ≥ λL + the smallest E_S, so candidates are
  // taken by increasing L and the search stops once no unsettled path can beat the best one.
  for (int L = 0; L <= s.levels + t.levels - 2; ++L) {
    if (lambda * L + floor_cost >= best) break;
    for (int ka = std::max(0, L - (t.levels - 1)); ka <= std::min(L, s.levels - 1); ++ka) {
      const int kb = L - ka;
      const double latency = lambda * L;
      for (int a = s.depth_start[ka]; a < s.depth_start[ka + 1]; ++a) {
        const Node& na = s.nodes[a];
        // s_lb ≤ the node's bound (convex weights of row maxima): skip what cannot win.
        if (scale * (1.0 - na.bound) + latency >= best) continue;
        for (int b = t.depth_start[kb]; b < t.depth_start[kb + 1]; ++b) {
          const Node& nb = t.nodes[b];
          if (scale * (1.0 - nb.bound) + latency >= best) continue;
          double similarity = 0;
          for (int i = 0; i < na.entries; ++i) {
            const float* row = matrix + na.index[i] * cols;
            double sum = 0;
            for (int j = 0; j < nb.entries; ++j) sum += nb.weight[j] * row[nb.index[j]];
            similarity += na.weight[i] * sum;
          }
          ++plan.evaluated_pairs;
          const double cost = scale * (1.0 - similarity) + latency;
          if (cost < best) {
            best = cost;
            best_a = a;
            best_b = b;
            plan.similarity = similarity;
          }
        }
      }
    }
  }
  plan.source_steps = s.nodes[best_a].depth;
  plan.target_steps = t.nodes[best_b].depth;
  plan.similarity_cost = scale * (1.0 - plan.similarity);
  plan.latency_cost = lambda * (plan.source_steps + plan.target_steps);
  return plan;
}

TransitionPlan TransitionPlanner::plan_cost(const MotionState& source, const MotionState& target) const {
  int a = 0, b = 0;
  return search(source, target, a, b);
}

TransitionPlan TransitionPlanner::plan(const MotionState& source, const MotionState& target) const {
  int best_a = 0, best_b = 0;
  TransitionPlan plan = search(source, target, best_a, best_b);
  const Node& na = source_side_.nodes[best_a];
  const Node& nb = target_side_.nodes[best_b];
  const auto d = static_cast<std::size_t>(from_->dimensions()), e = static_cast<std::size_t>(to_->dimensions());
  // Source levels 1..ka: time forward, parameters ramping linearly to the transition node's.
  for (int k = 1; k <= plan.source_steps; ++k) {
    MotionState state{source.space, from_->wrap(source.frame + k * source_side_.step), std::vector<double>(d)};
    for (std::size_t a = 0; a < d; ++a)
      state.parameters[a] = source.parameters[a] + (na.parameters[a] - source.parameters[a]) * k / plan.source_steps;
    plan.frames.push_back(std::move(state));
  }
  // Target levels kb..0: from the transition node forward in time to the target state.
  for (int k = plan.target_steps; k >= 0; --k) {
    MotionState state{target.space, to_->wrap(target.frame - k * target_side_.step), std::vector<double>(e)};
    for (std::size_t a = 0; a < e; ++a)
      state.parameters[a] = plan.target_steps == 0
                                ? target.parameters[a]
                                : nb.parameters[a] + (target.parameters[a] - nb.parameters[a]) *
                                                         (plan.target_steps - k) / plan.target_steps;
    plan.frames.push_back(std::move(state));
  }
  return plan;
}

double TransitionPlanner::similarity_bound(double from_frame, const double* from_u, double to_frame,
                                           const double* to_u) const {
  long a_nodes[8], b_nodes[8];
  double a_weights[8], b_weights[8];
  const int na = from_->cell_weights(from_u, a_nodes, a_weights), nb = to_->cell_weights(to_u, b_nodes, b_weights);
  const auto key = [](const SpaceEvaluator& space, double frame) {
    const int k = static_cast<int>(std::lround(space.wrap(frame)));
    return space.cyclic() ? k % space.frames() : std::min(k, space.frames() - 1);
  };
  const long ka = key(*from_, from_frame), kb = key(*to_, to_frame);
  double similarity = 0;
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j)
      similarity += a_weights[i] * b_weights[j] *
                    similarity_->at(a_nodes[i] * from_->frames() + ka, b_nodes[j] * to_->frames() + kb);
  return similarity;
}

}  // namespace surfcap::runtime
