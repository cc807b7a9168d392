#include "surfcap/runtime/space_evaluator.hpp"

#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::runtime {
namespace {

constexpr int kMaxCorners = 8;  // 2^d, d ≤ 3

}  // namespace

Eigen::Vector2d rotate_ground(const Eigen::Vector2d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v(0) + s * v(1), -s * v(0) + c * v(1)};
}

SpaceEvaluator::SpaceEvaluator(const asset::CharacterSpace& space) : space_(&space), vertices_(space.vertex_count()) {
  if (space.dimensions < 1 || space.dimensions > 3) throw core::bad_input(space.name, "a space needs 1–3 dimensions");
  displacement_values_.resize(space.displacement_values.size());
  for (std::size_t k = 0; k < displacement_values_.size(); ++k)
    displacement_values_[k] = core::half_to_float(space.displacement_values[k]);
  const int N = space.source_count(), T = space.frames;
  local_roots_.assign(static_cast<std::size_t>(N), std::vector<Eigen::Vector4d>(static_cast<std::size_t>(T + 1)));
  for (int i = 0; i < N; ++i) {
    const float* first = space.root_motion.data() + static_cast<std::size_t>(i) * T * 4;
    double turn = 0;
    for (int k = 0; k < T; ++k) {
      const float* now = first + k * 4;
      if (k > 0) turn += std::remainder(static_cast<double>(now[3]) - now[3 - 4], 2 * M_PI);
      // Displacement since the first frame, in the first frame's heading frame (R_y(−heading)·d).
      const Eigen::Vector2d local = rotate_ground({now[0] - first[0], now[2] - first[2]}, -first[3]);
      local_roots_[i][k] << local(0), now[1], local(1), turn;
    }
    // One step past the last frame, continuing its velocity: where the next cycle starts.
    local_roots_[i][T] = 2 * local_roots_[i][T - 1] - local_roots_[i][T - 2];
    local_roots_[i][T](1) = local_roots_[i][0](1);
  }
  for (int a = 0; a < space.dimensions; ++a) {
    if (space.parameter_map)
      parameter_range_.push_back({space.parameter_map->parameter_range(a, 0), space.parameter_map->parameter_range(a, 1)});
    else
      parameter_range_.push_back({0.0, 1.0});
  }
}

double SpaceEvaluator::wrap(double frame) const {
  if (cyclic()) {
    const double period = frames();
    frame = std::fmod(frame, period);
    return frame < 0 ? frame + period : frame;
  }
  return std::clamp(frame, 0.0, static_cast<double>(frames() - 1));
}

void SpaceEvaluator::weight_coordinates(const double* p, double* u) const {
  const int d = dimensions();
  if (!space_->parameter_map) {
    for (int a = 0; a < d; ++a) u[a] = std::clamp(p[a], 0.0, 1.0);
    return;
  }
  const blend::ParameterMap& map = *space_->parameter_map;
  for (int a = 0; a < d; ++a) {
    double value = 0;
    for (std::size_t k = 0; k < map.monomials.size(); ++k) {
      double term = map.coefficients(a, static_cast<long>(k));
      for (int j = 0; j < d; ++j)
        for (int e = 0; e < map.monomials[k][j]; ++e) term *= p[j];
      value += term;
    }
    u[a] = std::clamp(value, 0.0, 1.0);
  }
}

std::vector<double> SpaceEvaluator::parameters_for(const std::vector<double>& u) const {
  const int d = dimensions();
  const int steps = d == 1 ? 400 : d == 2 ? 100 : 30;
  long total = 1;
  for (int a = 0; a < d; ++a) total *= steps + 1;
  std::vector<double> best(static_cast<std::size_t>(d)), p(static_cast<std::size_t>(d)), v(static_cast<std::size_t>(d));
  double best_error = INFINITY;
  for (long index = 0; index < total; ++index) {
    long rest = index;
    for (int a = 0; a < d; ++a, rest /= steps + 1)
      p[a] = parameter_min(a) + (parameter_max(a) - parameter_min(a)) * static_cast<double>(rest % (steps + 1)) / steps;
    weight_coordinates(p.data(), v.data());
    double error = 0;
    for (int a = 0; a < d; ++a) error += (v[a] - u[a]) * (v[a] - u[a]);
    if (error < best_error) {
      best_error = error;
      best = p;
    }
  }
  return best;
}

void SpaceEvaluator::source_weights(const double* u, double* w) const {
  const int d = dimensions();
  for (int i = 0; i < (1 << d); ++i) {
    double weight = 1;
    for (int a = 0; a < d; ++a) weight *= (i >> a) & 1 ? u[a] : 1 - u[a];
    w[i] = weight;
  }
}

int SpaceEvaluator::cell_weights(const double* u, long* nodes, double* weights) const {
  const int d = dimensions();
  long base = 0, stride[3] = {1, 1, 1};
  double local[3] = {0, 0, 0};
  for (int a = 0; a < d; ++a) {
    const std::vector<double>& axis = space_->breakpoints[a];
    const double x = std::clamp(u[a], 0.0, 1.0);
    // Interval [axis[k], axis[k+1]] holding x (the last one for x = 1).
    const auto upper = std::upper_bound(axis.begin() + 1, axis.end() - 1, x);
    const long k = static_cast<long>(upper - axis.begin()) - 1;
    local[a] = (x - axis[k]) / (axis[k + 1] - axis[k]);
    if (a > 0) stride[a] = stride[a - 1] * static_cast<long>(space_->breakpoints[a - 1].size());
    base += k * stride[a];
  }
  int count = 0;
  for (int corner = 0; corner < (1 << d); ++corner) {
    double g = 1;
    long node = base;
    for (int a = 0; a < d; ++a) {
      const bool high = (corner >> a) & 1;
      g *= high ? local[a] : 1 - local[a];
      node += high ? stride[a] : 0;
    }
    if (g > 0) {
      nodes[count] = node;
      weights[count++] = g;
    }
  }
  return count;
}

double SpaceEvaluator::frames_per_step(const double* u, double fps) const {
  double w[kMaxCorners], duration = 0;
  source_weights(u, w);
  for (int i = 0; i < space_->source_count(); ++i) duration += w[i] * space_->sources[i].duration_s;
  return (frames() - 1) / std::max(1e-6, duration * fps);
}

void SpaceEvaluator::evaluate(double frame, const double* u, float* out) const {
  const long n = vertices_ * 3;
  const int T = frames();
  const double f = wrap(frame);
  const int k0 = std::min(static_cast<int>(f), T - 1);
  const double alpha = f - k0;
  const int k1 = cyclic() ? (k0 + 1) % T : std::min(k0 + 1, T - 1);
  const int keys[2] = {k0, k1};
  const double key_weights[2] = {1 - alpha, alpha};
  std::fill(out, out + n, 0.0f);
  double w[kMaxCorners];
  source_weights(u, w);
  for (int i = 0; i < space_->source_count(); ++i)
    for (int key = 0; key < 2; ++key) {
      const auto c = static_cast<float>(w[i] * key_weights[key]);
      if (c == 0) continue;
      const float* x = space_->references.data() + (static_cast<std::size_t>(i) * T + keys[key]) * n;
      for (long e = 0; e < n; ++e) out[e] += c * x[e];
    }
  long nodes[kMaxCorners];
  double g[kMaxCorners];
  const int cells = cell_weights(u, nodes, g);
  for (int j = 0; j < cells; ++j)
    for (int key = 0; key < 2; ++key) {
      const auto c = static_cast<float>(g[j] * key_weights[key]);
      if (c == 0) continue;
      const std::size_t row = static_cast<std::size_t>(nodes[j]) * T + keys[key];
      const auto end = space_->displacement_offsets[row + 1];
      for (auto e = space_->displacement_offsets[row]; e < end; ++e) {
        float* target = out + static_cast<std::size_t>(space_->displacement_vertices[e]) * 3;
        const float* value = displacement_values_.data() + e * 3;
        target[0] += c * value[0];
        target[1] += c * value[1];
        target[2] += c * value[2];
      }
    }
}

Eigen::Vector4d SpaceEvaluator::local_root(double frame, const double* w) const {
  const int T = frames();
  const double f = std::clamp(frame, 0.0, static_cast<double>(T));
  const int k0 = std::min(static_cast<int>(f), T - 1);
  const double alpha = f - k0;
  Eigen::Vector4d root = Eigen::Vector4d::Zero();
  for (int i = 0; i < space_->source_count(); ++i)
    if (w[i] != 0) root += w[i] * ((1 - alpha) * local_roots_[i][k0] + alpha * local_roots_[i][k0 + 1]);
  return root;
}

Eigen::Vector3d SpaceEvaluator::root_step(double f0, double f1, const double* u) const {
  double w[kMaxCorners];
  source_weights(u, w);
  // One segment [a, b] ⊂ [0, T]: displacement in the body frame at a, and the turn.
  const auto segment = [&](double a, double b) {
    const Eigen::Vector4d start = local_root(a, w), end = local_root(b, w);
    const Eigen::Vector2d body = rotate_ground({end(0) - start(0), end(2) - start(2)}, -start(3));
    return Eigen::Vector3d(body(0), body(1), end(3) - start(3));
  };
  f0 = wrap(f0);
  if (!cyclic()) return segment(f0, std::clamp(f1, f0, static_cast<double>(frames() - 1)));
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  double turned = 0, remaining = std::max(0.0, f1 - f0 + (f1 < f0 ? frames() : 0));
  double a = f0;
  while (remaining > 1e-12) {
    const double b = std::min(static_cast<double>(frames()), a + remaining);
    const Eigen::Vector3d step = segment(a, b);
    const Eigen::Vector2d moved = rotate_ground(step.head<2>(), turned);
    total += Eigen::Vector3d(moved(0), moved(1), step(2));
    turned += step(2);
    remaining -= b - a;
    a = b >= frames() ? 0.0 : b;
  }
  return total;
}

double SpaceEvaluator::root_height(double frame, const double* u) const {
  double w[kMaxCorners];
  source_weights(u, w);
  return local_root(wrap(frame), w)(1);
}

}  // namespace surfcap::runtime
