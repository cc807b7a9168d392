#include "surfcap/align/rigid_icp.hpp"

#include <flann/flann.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "surfcap/geometry/best_rotation.hpp"

namespace surfcap::align {

struct ColoredTarget::Index {
  std::vector<float> data;  // row-major n×6: position, scale × colour
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> tree;
};

ColoredTarget::ColoredTarget(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors,
                             double scale)
    : V_(V), F_(F), face_normals_(F.rows(), 3), scale_(scale), index_(std::make_unique<Index>()) {
  const auto n = static_cast<std::size_t>(V.rows());
  ring_start_.assign(n + 1, 0);
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    face_normals_.row(f) = (normal.norm() > 0 ? normal.normalized() : normal).transpose();
    for (int k = 0; k < 3; ++k) ++ring_start_[static_cast<std::size_t>(F(f, k)) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) ring_start_[i + 1] += ring_start_[i];
  ring_faces_.resize(static_cast<std::size_t>(ring_start_[n]));
  std::vector<int> fill(ring_start_.begin(), ring_start_.end() - 1);
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ring_faces_[static_cast<std::size_t>(fill[static_cast<std::size_t>(F(f, k))]++)] = static_cast<int>(f);
  index_->data.resize(6 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      index_->data[6 * i + static_cast<std::size_t>(k)] = static_cast<float>(V(static_cast<long>(i), k));
      index_->data[6 * i + 3 + static_cast<std::size_t>(k)] = static_cast<float>(scale * colors(static_cast<long>(i), k));
    }
  if (n == 0) return;
  const flann::Matrix<float> dataset(index_->data.data(), n, 6);
  index_->tree = std::make_unique<flann::Index<flann::L2_Simple<float>>>(dataset, flann::KDTreeSingleIndexParams(16));
  index_->tree->buildIndex();
}

ColoredTarget::~ColoredTarget() = default;

std::vector<int> ColoredTarget::nearest(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors) const {
  const auto q = static_cast<std::size_t>(points.rows());
  std::vector<int> indices(q, -1);
  if (!index_->tree || q == 0) return indices;
  std::vector<float> queries(6 * q);
  for (std::size_t i = 0; i < q; ++i)
    for (int k = 0; k < 3; ++k) {
      queries[6 * i + static_cast<std::size_t>(k)] = static_cast<float>(points(static_cast<long>(i), k));
      queries[6 * i + 3 + static_cast<std::size_t>(k)] = static_cast<float>(scale_ * colors(static_cast<long>(i), k));
    }
  std::vector<float> distances(q);
  flann::Matrix<float> query(queries.data(), q, 6);
  flann::Matrix<int> index_matrix(indices.data(), q, 1);
  flann::Matrix<float> distance_matrix(distances.data(), q, 1);
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);
  params.cores = 1;  // callers parallelise over frames
  index_->tree->knnSearch(query, index_matrix, distance_matrix, 1, params);
  return indices;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> ColoredTarget::closest_around(int vertex, const Eigen::Vector3d& p) const {
  Eigen::Vector3d best = V_.row(vertex).transpose(), normal = Eigen::Vector3d::Zero();
  double best_distance = std::numeric_limits<double>::infinity();
  for (int r = ring_start_[static_cast<std::size_t>(vertex)]; r < ring_start_[static_cast<std::size_t>(vertex) + 1]; ++r) {
    const int f = ring_faces_[static_cast<std::size_t>(r)];
    const Eigen::Vector3d q = geometry::closest_point_on_triangle(p, V_.row(F_(f, 0)).transpose(), V_.row(F_(f, 1)).transpose(),
                                                  V_.row(F_(f, 2)).transpose());
    const double distance = (q - p).squaredNorm();
    if (distance < best_distance) {
      best_distance = distance;
      best = q;
      normal = face_normals_.row(f).transpose();
    }
  }
  return {best, normal};
}

bool compatible_closest_point(const geometry::SurfaceQuery& target, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& normal, double max_distance, double normal_compatibility,
                              geometry::SurfacePoint& closest) {
  const auto within = target.closest_point_within(point, max_distance);
  if (!within || within->distance > max_distance) return false;
  closest = *within;
  return target.face_normal(closest.face).dot(normal) >= normal_compatibility;
}

namespace {

/// How many of `count` values the smallest `fraction` of them is: ⌈fraction · count⌉, at least 1
/// and at most `count`.
std::size_t smallest_count(std::size_t count, double fraction) {
  return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(count))), 1, count);
}

/// Reorders `values` (non-empty) so that its first `keep` are its smallest; returns the largest of
/// them.
double partition_smallest(std::vector<double>& values, std::size_t keep) {
  const auto nth = values.begin() + static_cast<std::ptrdiff_t>(keep - 1);
  std::nth_element(values.begin(), nth, values.end());
  return *nth;
}

/// Drops from `ok` every correspondence farther than the closest `fraction` of them (ties at the
/// threshold kept: the result depends on the distances only, not on the points' order).
void trim_farthest(const Eigen::MatrixXd& moved, const Eigen::MatrixXd& targets, double fraction, std::vector<char>& ok,
                   std::vector<double>& squared, std::vector<double>& kept) {
  squared.resize(static_cast<std::size_t>(moved.rows()));
  kept.clear();
  for (long i = 0; i < moved.rows(); ++i) {
    const auto at = static_cast<std::size_t>(i);
    if (!ok[at]) continue;
    squared[at] = (moved.row(i) - targets.row(i)).squaredNorm();
    kept.push_back(squared[at]);
  }
  if (kept.empty()) return;
  const std::size_t keep = smallest_count(kept.size(), fraction);
  if (keep == kept.size()) return;
  const double threshold = partition_smallest(kept, keep);
  for (std::size_t i = 0; i < squared.size(); ++i)
    if (ok[i] && squared[i] > threshold) ok[i] = 0;
}

/// Point-to-plane ICP with a small point-to-point term; `correspond(moved points, moved normals,
/// q, m, ok)` fills each point's target point q, target normal m and whether it is an inlier.
template <class Correspond>
RigidFit fit_rigid_with(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const IcpOptions& options,
                        const RigidFit& initial, Correspond&& correspond) {
  RigidFit fit = initial;
  const long k = points.rows();
  if (k == 0) return fit;
  const Eigen::Vector3d centre = points.colwise().mean().transpose();
  Eigen::MatrixXd moved(k, 3), moved_normals(k, 3), targets(k, 3), target_normals(k, 3);
  std::vector<char> ok(static_cast<std::size_t>(k));
  std::vector<double> squared, kept;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    long inliers = 0;
    double distance_sum = 0;
    const Eigen::Vector3d moved_centre = fit.apply(centre);
    for (long i = 0; i < k; ++i) {
      moved.row(i) = fit.apply(points.row(i).transpose()).transpose();
      moved_normals.row(i) = (fit.rotation * normals.row(i).transpose()).transpose();
    }
    correspond(moved, moved_normals, targets, target_normals, ok);
    if (options.trim_fraction < 1) trim_farthest(moved, targets, options.trim_fraction, ok, squared, kept);
    for (long i = 0; i < k; ++i) {
      if (!ok[static_cast<std::size_t>(i)]) continue;
      const Eigen::Vector3d p = moved.row(i).transpose();
      const Eigen::Vector3d q = targets.row(i).transpose();
      const Eigen::Vector3d m = target_normals.row(i).transpose();
      ++inliers;
      distance_sum += (p - q).norm();
      const Eigen::Vector3d s = p - moved_centre;  // rotate about the centroid: better conditioned
      // Point-to-plane row: [s×m, m]·[ω, t] = −m·(p − q).
      Eigen::Matrix<double, 6, 1> row;
      row << s.cross(m), m;
      normal_matrix += row * row.transpose();
      rhs -= row * m.dot(p - q);
      // Point-to-point rows: [−[s]×, I]·[ω, t] = −(p − q).
      Eigen::Matrix<double, 3, 6> block;
      block << 0, s.z(), -s.y(), 1, 0, 0,  //
          -s.z(), 0, s.x(), 0, 1, 0,       //
          s.y(), -s.x(), 0, 0, 0, 1;
      normal_matrix += options.point_to_point_weight * block.transpose() * block;
      rhs -= options.point_to_point_weight * block.transpose() * (p - q);
    }
    fit.inliers = inliers;
    fit.mean_distance = inliers > 0 ? distance_sum / static_cast<double>(inliers) : 0.0;
    if (inliers < 6) break;
    const Eigen::Matrix<double, 6, 1> step = normal_matrix.ldlt().solve(rhs);
    if (!step.allFinite()) break;
    const Eigen::Vector3d omega = step.head<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d rotation_step =
        angle > 1e-15 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    // x ↦ R_step (x − c) + c + t_step with c the moved centre.
    fit.rotation = rotation_step * fit.rotation;
    fit.translation = rotation_step * (fit.translation - moved_centre) + moved_centre + step.tail<3>();
    if (angle < 1e-7 && step.tail<3>().norm() < 1e-7) break;
  }
  return fit;
}

}  // namespace

RigidFit fit_rigid(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const geometry::SurfaceQuery& target,
                   const IcpOptions& options, const RigidFit& initial) {
  return fit_rigid_with(points, normals, options, initial,
                        [&](const Eigen::MatrixXd& moved, const Eigen::MatrixXd& moved_normals, Eigen::MatrixXd& q,
                            Eigen::MatrixXd& m, std::vector<char>& ok) {
                          for (long i = 0; i < moved.rows(); ++i) {
                            geometry::SurfacePoint closest;
                            ok[static_cast<std::size_t>(i)] = compatible_closest_point(
                                target, moved.row(i).transpose(), moved_normals.row(i).transpose(),
                                options.max_distance, options.normal_compatibility, closest);
                            if (!ok[static_cast<std::size_t>(i)]) continue;
                            q.row(i) = closest.position.transpose();
                            m.row(i) = target.face_normal(closest.face).transpose();
                          }
                        });
}

RigidFit fit_rigid(const Eigen::MatrixXd& points, const Eigen::MatrixXd& normals, const Eigen::MatrixXd& colors,
                   const ColoredTarget& colored, const IcpOptions& options, const RigidFit& initial) {
  return fit_rigid_with(points, normals, options, initial,
                        [&](const Eigen::MatrixXd& moved, const Eigen::MatrixXd& moved_normals, Eigen::MatrixXd& q,
                            Eigen::MatrixXd& m, std::vector<char>& ok) {
                          const std::vector<int> nearest = colored.nearest(moved, colors);
                          for (long i = 0; i < moved.rows(); ++i) {
                            const int j = nearest[static_cast<std::size_t>(i)];
                            auto& inlier = ok[static_cast<std::size_t>(i)];
                            inlier = 0;
                            if (j < 0) continue;
                            const auto [x, n] = colored.closest_around(j, moved.row(i).transpose());
                            if ((x - moved.row(i).transpose()).norm() > options.max_distance) continue;
                            if (n.dot(moved_normals.row(i).transpose()) < options.normal_compatibility) continue;
                            inlier = 1;
                            q.row(i) = x.transpose();
                            m.row(i) = n.transpose();
                          }
                        });
}

Eigen::MatrixXd transformed(const Eigen::MatrixXd& points, const RigidFit& fit) {
  return ((points * fit.rotation.transpose()).rowwise() + fit.translation.transpose()).eval();
}

namespace {

/// The mean of the smallest `fraction` of `values` (all of them, summed in their order, when it is
/// 1; otherwise summed sorted, so the result does not depend on nth_element's order). Reorders.
double mean_of_smallest(std::vector<double>& values, double fraction) {
  if (values.empty()) return 0.0;
  const std::size_t keep = smallest_count(values.size(), fraction);
  if (keep < values.size()) {
    partition_smallest(values, keep);
    std::sort(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(keep));
  }
  double sum = 0;
  for (std::size_t i = 0; i < keep; ++i) sum += values[i];
  return sum / static_cast<double>(keep);
}

}  // namespace

double clamped_mean_distance(const Eigen::MatrixXd& points, const geometry::SurfaceQuery& target, double gate,
                             double fraction) {
  std::vector<double> distances(static_cast<std::size_t>(points.rows()));
  for (long i = 0; i < points.rows(); ++i) {
    const auto closest = target.closest_point_within(points.row(i).transpose(), gate);
    distances[static_cast<std::size_t>(i)] = closest ? std::min(gate, closest->distance) : gate;
  }
  return mean_of_smallest(distances, fraction);
}

Eigen::RowVector3d interpolated_colour(const geometry::SurfaceQuery& target, const Eigen::MatrixXd& colors,
                                      const geometry::SurfacePoint& point) {
  Eigen::RowVector3d colour = Eigen::RowVector3d::Zero();
  for (int k = 0; k < 3; ++k) colour += point.barycentric[k] * colors.row(target.faces()(point.face, k));
  return colour;
}

double clamped_mean_joint_distance(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors,
                                   const geometry::SurfaceQuery& target, const Eigen::MatrixXd& target_colors,
                                   double scale, double gate, double fraction) {
  std::vector<double> distances(static_cast<std::size_t>(points.rows()), gate);
  for (long i = 0; i < points.rows(); ++i) {
    const auto closest = target.closest_point_within(points.row(i).transpose(), gate);
    if (!closest) continue;
    const double colour = (interpolated_colour(target, target_colors, *closest) - colors.row(i)).squaredNorm();
    const double joint = std::sqrt(closest->distance * closest->distance + scale * scale * colour);
    distances[static_cast<std::size_t>(i)] = std::min(gate, joint);
  }
  return mean_of_smallest(distances, fraction);
}

RigidFit best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  const Eigen::Matrix4d motion = geometry::best_rigid_motion(from, to);
  RigidFit fit;
  fit.rotation = motion.topLeftCorner<3, 3>();
  fit.translation = motion.topRightCorner<3, 1>();
  return fit;
}

}  // namespace surfcap::align
