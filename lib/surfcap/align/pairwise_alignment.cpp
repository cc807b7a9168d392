#include "surfcap/align/pairwise_alignment.hpp"

#include <Eigen/Geometry>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "surfcap/align/creases.hpp"
#include "surfcap/align/feature_constraints.hpp"
#include "surfcap/align/rigid_icp.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::align {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double mean_edge_length(const core::Mesh& mesh) {
  double sum = 0;
  for (long f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) sum += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  return mesh.F.rows() > 0 ? sum / (3.0 * static_cast<double>(mesh.F.rows())) : 0.0;
}

/// Mean over `points` of the distance to the target, clamped at `gate` (unmatched points count as gate).
double clamped_mean_distance(const Eigen::MatrixXd& points, const geometry::SurfaceQuery& target, double gate) {
  double sum = 0;
  for (long i = 0; i < points.rows(); ++i) sum += std::min(gate, target.closest_point(points.row(i).transpose()).distance);
  return points.rows() > 0 ? sum / static_cast<double>(points.rows()) : 0.0;
}

Eigen::MatrixXd transformed(const Eigen::MatrixXd& points, const RigidFit& fit) {
  return ((points * fit.rotation.transpose()).rowwise() + fit.translation.transpose()).eval();
}

/// The rigid motion best taking `from` onto `to` (rows paired; Eigen's Umeyama, no scaling).
RigidFit best_rigid_motion(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  const Eigen::Matrix4d motion = Eigen::umeyama(from.transpose(), to.transpose(), false);
  RigidFit fit;
  fit.rotation = motion.topLeftCorner<3, 3>();
  fit.translation = motion.topRightCorner<3, 1>();
  return fit;
}

/// Mean squared colour difference between `points` (with `colors`) and the reconstruction's
/// (smoothed, interpolated) colour at their closest points; points farther than `gate` count as a
/// full disagreement (1).
double colour_disagreement(const Eigen::MatrixXd& points, const Eigen::MatrixXd& colors,
                           const geometry::SurfaceQuery& target, const Eigen::MatrixXd& target_colors, double gate) {
  double sum = 0;
  for (long i = 0; i < points.rows(); ++i) {
    const geometry::SurfacePoint closest = target.closest_point(points.row(i).transpose());
    if (closest.face < 0 || closest.distance > gate) {
      sum += 1;
      continue;
    }
    Eigen::RowVector3d colour = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 3; ++k) colour += closest.barycentric[k] * target_colors.row(target.faces()(closest.face, k));
    sum += std::min(1.0, (colour - colors.row(i)).squaredNorm());
  }
  return points.rows() > 0 ? sum / static_cast<double>(points.rows()) : 0.0;
}

/// Target vertices binned on a uniform grid, for radius searches.
class VertexGrid {
 public:
  VertexGrid(const Eigen::MatrixXd& V, double cell) : V_(V), cell_(cell) {
    for (long v = 0; v < V.rows(); ++v) bins_[key(V.row(v).transpose())].push_back(v);
  }
  template <class Visit>
  void around(const Eigen::Vector3d& p, Visit&& visit) const {
    const Eigen::Vector3i c = (p / cell_).array().floor().cast<int>();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = bins_.find(pack(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == bins_.end()) continue;
          for (const long v : it->second) visit(v);
        }
  }

 private:
  static std::int64_t pack(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x() & 0x1FFFFF) << 42) | (static_cast<std::int64_t>(c.y() & 0x1FFFFF) << 21) |
           static_cast<std::int64_t>(c.z() & 0x1FFFFF);
  }
  std::int64_t key(const Eigen::Vector3d& p) const { return pack((p / cell_).array().floor().cast<int>()); }
  const Eigen::MatrixXd& V_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<long>> bins_;
};

}  // namespace

RigidFit rigid_initialisation(const Eigen::MatrixXd& surface, const Eigen::MatrixXd& normals,
                              const geometry::SurfaceQuery& target, const AlignmentTemplate& model,
                              const PairwiseOptions& options) {
  // A subsample keeps the initialisation cheap; every k-th vertex, deterministic.
  const long step = std::max<long>(1, surface.rows() / 800);
  const long count = (surface.rows() + step - 1) / step;
  Eigen::MatrixXd points(count, 3), point_normals(count, 3);
  for (long i = 0; i < count; ++i) {
    points.row(i) = surface.row(i * step);
    point_normals.row(i) = normals.row(i * step);
  }
  const Eigen::Vector3d source_centre = points.colwise().mean().transpose();
  const Eigen::Vector3d target_centre = target.vertices().colwise().mean().transpose();
  IcpOptions icp;
  icp.max_distance = 2 * options.coarse_distance_height * model.height();
  icp.normal_compatibility = options.normal_compatibility;
  icp.iterations = 12;
  const double gate = icp.max_distance;
  auto attempt = [&](double heading) {
    RigidFit start;
    start.rotation = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix();
    start.translation = target_centre - start.rotation * source_centre;
    RigidFit fit = fit_rigid(points, point_normals, target, icp, start);
    return std::pair{fit, clamped_mean_distance(transformed(points, fit), target, gate)};
  };
  auto [best, best_score] = attempt(0.0);
  if (best_score <= 1.5 * model.mean_edge() || options.heading_samples <= 1) return best;
  for (int k = 1; k < options.heading_samples; ++k) {
    const auto [fit, score] = attempt(2 * std::numbers::pi * k / options.heading_samples);
    if (score < best_score) {
      best = fit;
      best_score = score;
    }
  }
  return best;
}

double stacked_fraction(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& aligned, const Eigen::MatrixXi& F,
                        double distance, double rest_distance) {
  const long n = aligned.rows();
  if (n == 0 || distance <= 0) return 0.0;
  const Eigen::MatrixXd normals = core::vertex_normals(aligned, F);
  const VertexGrid grid(aligned, distance);
  std::vector<char> stacked(static_cast<std::size_t>(n), 0);
  const double d2 = distance * distance, r2 = rest_distance * rest_distance;
  for (long v = 0; v < n; ++v)
    grid.around(aligned.row(v).transpose(), [&](long u) {
      if (u <= v || (aligned.row(u) - aligned.row(v)).squaredNorm() > d2) return;
      if ((rest.row(u) - rest.row(v)).squaredNorm() <= r2 || normals.row(u).dot(normals.row(v)) <= 0.5) return;
      stacked[static_cast<std::size_t>(u)] = stacked[static_cast<std::size_t>(v)] = 1;
    });
  return static_cast<double>(std::count(stacked.begin(), stacked.end(), 1)) / static_cast<double>(n);
}

AlignmentTemplate::AlignmentTemplate(core::Mesh mesh, const PairwiseOptions& options, const DeformerOptions& deformer)
    : seconds_tetrahedralisation_(0),
      mesh_(std::move(mesh)),
      deformer_([&] {
        const auto start = Clock::now();
        VolumeDeformer built(mesh_, deformer);
        seconds_tetrahedralisation_ = seconds_since(start);
        return built;
      }()),
      patches_(patch_hierarchy(mesh_.V, mesh_.F, options.patches, options.levels)),
      mean_edge_(mean_edge_length(mesh_)),
      height_(mesh_.V.col(1).maxCoeff() - mesh_.V.col(1).minCoeff()) {
  if (mesh_.has_colors()) smoothed_colors_ = smoothed_vertex_colors(mesh_.F, mesh_.colors, options.patch_color.smoothing);
  if (options.crease.weight)
    crease_vertices_ = straight_crease_vertices(
        mesh_.V, convex_crease_vertices(mesh_.V, mesh_.F, options.crease.angle_deg * std::numbers::pi / 180),
        options.crease.straight_radius_height * height_, options.crease.straightness.value_or(1.0));
}

Eigen::MatrixXd smoothed_vertex_colors(const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors, int rings) {
  Eigen::MatrixXd current = colors;
  if (rings <= 0 || colors.rows() == 0) return current;
  // Each face adds a vertex's two neighbours in it: a neighbour across an interior edge counts twice
  // (once per face sharing the edge), a uniform weighting on a closed mesh.
  Eigen::VectorXd count = Eigen::VectorXd::Ones(colors.rows());
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) count(F(f, k)) += 2;
  for (int ring = 0; ring < rings; ++ring) {
    Eigen::MatrixXd sum = current;
    for (long f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
        sum.row(a) += current.row(b) + current.row(c);
      }
    current = sum.array().colwise() / count.array();
  }
  return current;
}

Eigen::VectorXd surface_distances(const Eigen::MatrixXd& surface, const geometry::SurfaceQuery& target) {
  Eigen::VectorXd distances(surface.rows());
  for (long i = 0; i < surface.rows(); ++i) distances(i) = target.closest_point(surface.row(i).transpose()).distance;
  return distances;
}

PairwiseResult align_pair(const AlignmentTemplate& model, const Eigen::MatrixXd& parent_positions,
                          const geometry::SurfaceQuery& target, const PairwiseOptions& options,
                          const Eigen::MatrixXd* target_colors, const FeaturePair& features,
                          const Eigen::MatrixXd* predicted_surface) {
  const VolumeDeformer& deformer = model.deformer();
  const long surface_count = deformer.surface_vertex_count();
  const Eigen::MatrixXi& F = model.mesh().F;
  if (parent_positions.rows() != deformer.vertex_count()) throw core::internal_error("align_pair: parent size");
  if (predicted_surface != nullptr && predicted_surface->rows() != surface_count)
    throw core::internal_error("align_pair: predicted surface size");
  PairwiseResult result;
  result.predicted = predicted_surface != nullptr;
  Eigen::MatrixXd positions = parent_positions;

  auto start = Clock::now();
  std::vector<FeatureConstraint> feature_targets;
  {
    const Eigen::MatrixXd surface = positions.topRows(surface_count);
    const RigidFit rigid = rigid_initialisation(surface, core::vertex_normals(surface, F), target, model, options);
    positions = transformed(positions, rigid);
    const Eigen::Vector3d forward = rigid.rotation * Eigen::Vector3d::UnitZ();
    result.heading_change = std::atan2(forward.x(), forward.z());
    if (options.feature.weight && features.parent != nullptr && features.child != nullptr) {
      FeatureMatching matching =
          feature_constraints(surface, F, *features.parent, *features.child, rigid.rotation, rigid.translation,
                              options.dense_distance_edges * model.mean_edge(), model.height(), options.feature);
      feature_targets = std::move(matching.constraints);
      result.feature_constraints = static_cast<long>(feature_targets.size());
    }
  }
  result.timings.matching += seconds_since(start);

  auto solve = [&](const Eigen::MatrixXd& targets, const Eigen::VectorXd& weights) {
    auto begin = Clock::now();
    const geometry::SparseCholesky solver = deformer.factor(weights);
    result.timings.factorisation += seconds_since(begin);
    begin = Clock::now();
    positions = deformer.deform(solver, positions, targets, weights, options.rotation_iterations);
    result.timings.solves += seconds_since(begin);
  };

  // Appearance flow (drift-free, dense): where the child's images show each template point, by
  // optical flow from the template rendered with the root frame's appearance; overrides other targets.
  const bool use_flow = options.flow.weight && features.appearance != nullptr && features.child_images != nullptr &&
                        !features.child_images->empty();
  auto add_flow_targets = [&](const Eigen::MatrixXd& surface, Eigen::MatrixXd& targets, Eigen::VectorXd& weights) {
    const FlowTargets flow = flow_targets(*features.appearance, surface, F, *features.child_images, target,
                                          model.mean_edge(), options.flow);
    result.flow_pixels = flow.pixels;
    result.flow_vertices = 0;
    for (long v = 0; v < surface_count; ++v) {
      if (flow.support(v) <= 0) continue;
      targets.row(v) = flow.targets.row(v);
      weights(v) = *options.flow.weight * std::min(1.0, flow.support(v));
      ++result.flow_vertices;
    }
  };

  // Coverage (child → template) constraints: every reconstruction vertex farther than the uncovered
  // gate from the aligned template (but within `reach`) pulls its closest template point towards it,
  // so that a limb left behind or collapsed onto another is drawn to the part it should cover.
  const Eigen::MatrixXd target_normals = core::vertex_normals(target.vertices(), target.faces());
  auto add_coverage_targets = [&](const Eigen::MatrixXd& surface, double reach, Eigen::MatrixXd& targets,
                                  Eigen::VectorXd& weights) {
    if (!options.coverage.weight) return;
    const geometry::SurfaceQuery aligned(surface, F);
    const double gate = options.checks.uncovered_distance_edges * model.mean_edge();
    std::vector<FeatureConstraint> pulls;
    for (long i = 0; i < target.vertices().rows(); ++i) {
      const Eigen::Vector3d x = target.vertices().row(i).transpose();
      const geometry::SurfacePoint closest = aligned.closest_point(x);
      if (closest.face < 0 || closest.distance <= gate || closest.distance > reach) continue;
      if (aligned.face_normal(closest.face).dot(target_normals.row(i).transpose()) < options.normal_compatibility) continue;
      pulls.push_back({closest.face, closest.barycentric, x});
    }
    result.coverage_constraints = static_cast<long>(pulls.size());
    add_feature_targets(surface, F, pulls, *options.coverage.weight, targets, weights);
  };

  // Crease matching: the template's rim vertices to the reconstruction's convex creases.
  std::unique_ptr<CreaseLines> crease_lines;
  if (options.crease.weight && !model.crease_vertices().empty()) {
    start = Clock::now();
    crease_lines = std::make_unique<CreaseLines>(target.vertices(), target.faces(),
                                                 options.crease.angle_deg * std::numbers::pi / 180,
                                                 options.crease.distance_edges * model.mean_edge());
    result.timings.matching += seconds_since(start);
  }
  auto add_crease_targets = [&](const Eigen::MatrixXd& surface, Eigen::MatrixXd& targets, Eigen::VectorXd& weights) {
    if (!crease_lines) return;
    const Eigen::MatrixXd normals = core::vertex_normals(surface, F);
    const double gate = options.crease.distance_edges * model.mean_edge();
    result.crease_constraints = 0;
    for (const int v : model.crease_vertices()) {
      Eigen::Vector3d point;
      if (!crease_lines->closest(surface.row(v).transpose(), normals.row(v).transpose(), gate,
                                 options.normal_compatibility, point))
        continue;
      targets.row(v) = point.transpose();
      weights(v) = *options.crease.weight;
      ++result.crease_constraints;
    }
  };

  // Colour-aware patch correspondences when both meshes have colours.
  std::unique_ptr<ColoredTarget> colored;
  Eigen::MatrixXd target_smoothed_colors;
  if (options.patch_color.scale && options.patch_color.levels > 0 && model.smoothed_colors().rows() == surface_count &&
      target_colors != nullptr &&
      target_colors->rows() == target.vertices().rows()) {
    start = Clock::now();
    target_smoothed_colors = smoothed_vertex_colors(target.faces(), *target_colors, options.patch_color.smoothing);
    colored = std::make_unique<ColoredTarget>(target.vertices(), target.faces(), target_smoothed_colors,
                                              *options.patch_color.scale);
    result.timings.matching += seconds_since(start);
  }

  // Coarse-to-fine rigid patch matching (casas2011 §3.2): the patch fits become soft constraints.
  for (std::size_t level = 0; level < model.patches().size(); ++level) {
    start = Clock::now();
    const PatchSet& patches = model.patches()[level];
    const Eigen::MatrixXd surface = positions.topRows(surface_count);
    const Eigen::MatrixXd normals = core::vertex_normals(surface, F);
    IcpOptions icp;
    icp.iterations = options.patch_icp_iterations;
    icp.normal_compatibility = options.normal_compatibility;
    icp.max_distance = std::max(options.coarse_distance_height * model.height() / std::pow(2.0, static_cast<double>(level)),
                                options.dense_distance_edges * model.mean_edge());
    Eigen::MatrixXd targets = surface;
    Eigen::VectorXd weights = Eigen::VectorXd::Zero(surface_count);
    for (const auto& members : patches.vertices) {
      const long size = static_cast<long>(members.size());
      Eigen::MatrixXd points(size, 3), point_normals(size, 3), point_colors(colored ? size : 0, 3);
      for (long i = 0; i < size; ++i) {
        points.row(i) = surface.row(members[static_cast<std::size_t>(i)]);
        point_normals.row(i) = normals.row(members[static_cast<std::size_t>(i)]);
        if (colored) point_colors.row(i) = model.smoothed_colors().row(members[static_cast<std::size_t>(i)]);
      }
      RigidFit fit = fit_rigid(points, point_normals, target, icp);
      if (colored && static_cast<int>(level) < options.patch_color.levels) {
        // Model selection per patch: the colour-aware fit replaces the closest-point fit only when
        // the patch's colours agree clearly better with the reconstruction's where it lands.
        const RigidFit colour_fit = fit_rigid(points, point_normals, point_colors, *colored, icp);
        const double closest_score = colour_disagreement(transformed(points, fit), point_colors, target,
                                                         target_smoothed_colors, icp.max_distance);
        const double colour_score = colour_disagreement(transformed(points, colour_fit), point_colors, target,
                                                        target_smoothed_colors, icp.max_distance);
        if (colour_score < options.patch_color.gain * closest_score) {
          fit = colour_fit;
          ++result.color_patches;
        }
      }
      if (predicted_surface != nullptr && static_cast<int>(level) < options.prediction.levels) {
        // Model selection per patch: a fit started where the motion prediction puts the patch
        // (the rigid motion taking it there) replaces the fit from the parent's pose when it
        // lies clearly closer to the reconstruction with no fewer compatible matches — a limb
        // swinging farther in one frame than the correspondence gate is found where it went.
        Eigen::MatrixXd goal(size, 3);
        for (long i = 0; i < size; ++i) goal.row(i) = predicted_surface->row(members[static_cast<std::size_t>(i)]);
        const RigidFit predicted_fit = fit_rigid(points, point_normals, target, icp, best_rigid_motion(points, goal));
        const double current_score = clamped_mean_distance(transformed(points, fit), target, icp.max_distance);
        const double predicted_score = clamped_mean_distance(transformed(points, predicted_fit), target, icp.max_distance);
        if (predicted_score < options.prediction.gain * current_score && predicted_fit.inliers >= fit.inliers) {
          fit = predicted_fit;
          ++result.predicted_patches;
        }
      }
      ++result.total_patches;
      if (static_cast<double>(fit.inliers) < options.min_patch_inliers * static_cast<double>(members.size())) continue;
      ++result.accepted_patches;
      for (const int v : members) {
        targets.row(v) = fit.apply(surface.row(v).transpose()).transpose();
        weights(v) = options.patch_weight;
      }
      result.patch_constraints += static_cast<long>(members.size());
    }
    if (static_cast<int>(level) >= static_cast<int>(model.patches().size()) - options.crease.patch_levels)
      add_crease_targets(surface, targets, weights);
    add_coverage_targets(surface, icp.max_distance, targets, weights);
    add_feature_targets(surface, F, feature_targets, options.feature.weight.value_or(0), targets, weights);
    result.timings.matching += seconds_since(start);
    if (weights.maxCoeff() > 0) solve(targets, weights);
  }

  // Dense fit: every surface vertex towards its compatible closest point on the reconstruction.
  const double dense_gate = options.dense_distance_edges * model.mean_edge();
  const double color_radius = options.color.radius_edges * model.mean_edge();
  std::unique_ptr<VertexGrid> grid;
  if (options.color.sigma && target_colors != nullptr && model.mesh().has_colors() &&
      target_colors->rows() == target.vertices().rows())
    grid = std::make_unique<VertexGrid>(target.vertices(), color_radius);
  // Each surface vertex towards its compatible closest point on the reconstruction (or, with
  // colours, the colour-weighted target near it); returns the number of vertices matched.
  auto dense_targets = [&](const Eigen::MatrixXd& surface, Eigen::MatrixXd& targets, Eigen::VectorXd& weights) {
    const Eigen::MatrixXd normals = core::vertex_normals(surface, F);
    long matched = 0;
    result.color_constraints = 0;
    for (long v = 0; v < surface_count; ++v) {
      geometry::SurfacePoint closest;
      if (!compatible_closest_point(target, surface.row(v).transpose(), normals.row(v).transpose(), dense_gate,
                                    options.normal_compatibility, closest))
        continue;
      Eigen::Vector3d goal = closest.position;
      if (grid) {
        // Photometric target: target vertices near the closest point, weighted by colour agreement.
        const Eigen::Vector3d colour = model.mesh().colors.row(v).transpose();
        const double radius2 = color_radius * color_radius;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        double weight_sum = 0;
        grid->around(closest.position, [&](long j) {
          const Eigen::Vector3d x = target.vertices().row(j).transpose();
          const double d2 = (x - closest.position).squaredNorm();
          if (d2 > radius2) return;
          const double c2 = (target_colors->row(j).transpose() - colour).squaredNorm();
          const double w = std::exp(-c2 / (2 * *options.color.sigma * *options.color.sigma) - d2 / (2 * radius2 / 4));
          sum += w * x;
          weight_sum += w;
        });
        if (weight_sum > 1e-6) {
          const geometry::SurfacePoint projected = target.closest_point(sum / weight_sum);
          if (target.face_normal(projected.face).dot(normals.row(v).transpose()) >= options.normal_compatibility) {
            goal = projected.position;
            ++result.color_constraints;
          }
        }
      }
      targets.row(v) = goal.transpose();
      weights(v) = options.dense_weight;
      ++matched;
    }
    return matched;
  };
  for (int iteration = 0; iteration < options.dense_iterations; ++iteration) {
    start = Clock::now();
    const Eigen::MatrixXd surface = positions.topRows(surface_count);
    Eigen::MatrixXd targets = surface;
    Eigen::VectorXd weights = Eigen::VectorXd::Zero(surface_count);
    const long matched = dense_targets(surface, targets, weights);
    result.dense_constraints = matched;
    add_crease_targets(surface, targets, weights);
    add_coverage_targets(surface, options.coarse_distance_height * model.height(), targets, weights);
    add_feature_targets(surface, F, feature_targets, options.feature.weight.value_or(0), targets, weights);
    result.timings.matching += seconds_since(start);
    if (matched == 0) break;
    solve(targets, weights);
  }

  // Appearance-flow iterations after the dense fit.
  if (use_flow) {
    for (int iteration = 0; iteration < options.flow.iterations; ++iteration) {
      start = Clock::now();
      const Eigen::MatrixXd surface = positions.topRows(surface_count);
      Eigen::MatrixXd targets = surface;
      Eigen::VectorXd weights = Eigen::VectorXd::Zero(surface_count);
      result.dense_constraints = dense_targets(surface, targets, weights);
      add_flow_targets(surface, targets, weights);
      add_crease_targets(surface, targets, weights);
      add_coverage_targets(surface, options.coarse_distance_height * model.height(), targets, weights);
      add_feature_targets(surface, F, feature_targets, options.feature.weight.value_or(0), targets, weights);
      result.timings.matching += seconds_since(start);
      if (weights.maxCoeff() <= 0) break;
      solve(targets, weights);
    }
    }

  start = Clock::now();
  const Eigen::VectorXd distances = surface_distances(positions.topRows(surface_count), target);
  result.mean_residual = distances.mean();
  result.max_residual = distances.maxCoeff();
  {
    // Two-sided check: reconstruction vertices far from the aligned template are parts it missed
    // (a limb collapsed onto another leaves one uncovered) — the one-sided residual cannot see that.
    const geometry::SurfaceQuery aligned(positions.topRows(surface_count), F);
    const double gate = options.checks.uncovered_distance_edges * model.mean_edge();
    long uncovered = 0;
    for (long i = 0; i < target.vertices().rows(); ++i)
      if (aligned.closest_point(target.vertices().row(i).transpose()).distance > gate) ++uncovered;
    result.uncovered_fraction =
        target.vertices().rows() > 0 ? static_cast<double>(uncovered) / static_cast<double>(target.vertices().rows()) : 0.0;
  }
  result.stacked_fraction = stacked_fraction(model.mesh().V, positions.topRows(surface_count), F,
                                             options.checks.stacked_distance_edges * model.mean_edge(),
                                             options.checks.stacked_rest_distance_height * model.height());
  result.timings.matching += seconds_since(start);
  result.positions = std::move(positions);
  return result;
}

}  // namespace surfcap::align
