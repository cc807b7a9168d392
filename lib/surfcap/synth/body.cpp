#include "surfcap/synth/body.hpp"

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_with_circumcenter_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Random.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_cell_base_3.h>
#include <CGAL/Surface_mesh_default_criteria_3.h>
#include <CGAL/Surface_mesh_vertex_base_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/surface_mesh_copy.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::synth {
namespace {

/// A triangulation element base with a CGAL time stamp. CGAL compares handles of time-stamped
/// elements by creation order, otherwise by address: the surface mesher keeps its refinement
/// queues and vertex sets ordered by handle, so without stamps its mesh depends on where the
/// allocator puts the triangulation's blocks (it differed between runs under ASan, and between two
/// meshings in one process). Mesh_3's own bases carry stamps for the same reason.
template <class Base>
class TimeStamped : public Base {
 public:
  using Has_timestamp = CGAL::Tag_true;
  using Base::Base;
  template <class Tds>
  struct Rebind_TDS {
    using Other = TimeStamped<typename Base::template Rebind_TDS<Tds>::Other>;
  };
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& stamp) { time_stamp_ = stamp; }

 private:
  std::size_t time_stamp_ = std::size_t(-1);
};

// CGAL::Surface_mesh_default_triangulation_3 with time-stamped vertices and cells.
using Traits = CGAL::Robust_circumcenter_traits_3<CGAL::Exact_predicates_inexact_constructions_kernel>;
using VertexBase = TimeStamped<CGAL::Surface_mesh_vertex_base_3<Traits>>;
using CellBase = TimeStamped<
    CGAL::Delaunay_triangulation_cell_base_with_circumcenter_3<Traits, CGAL::Surface_mesh_cell_base_3<Traits>>>;
using Triangulation = CGAL::Delaunay_triangulation_3<Traits, CGAL::Triangulation_data_structure_3<VertexBase, CellBase>>;
using Complex = CGAL::Complex_2_in_triangulation_3<Triangulation>;
using Point = Traits::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

double smooth_min(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// Distance of p to a flat-capped cone around the vertical axis through (0, ·, 0), from height
/// `top` (radius r_top) down to `bottom` (radius r_bottom); Quílez's exact capped-cone distance.
double capped_cone_distance(const Eigen::Vector3d& p, double top, double bottom, double r_top, double r_bottom,
                            double depth_scale) {
  const double h = 0.5 * (top - bottom);
  const Eigen::Vector2d q(std::hypot(p.x(), p.z() / depth_scale), p.y() - 0.5 * (top + bottom));
  const Eigen::Vector2d k1(r_top, h), k2(r_top - r_bottom, 2 * h);
  const Eigen::Vector2d ca(q.x() - std::min(q.x(), q.y() < 0 ? r_bottom : r_top), std::abs(q.y()) - h);
  const Eigen::Vector2d cb = q - k1 + k2 * std::clamp((k1 - q).dot(k2) / k2.squaredNorm(), 0.0, 1.0);
  const double sign = (cb.x() < 0 && ca.y() < 0) ? -1.0 : 1.0;
  return sign * std::sqrt(std::min(ca.squaredNorm(), cb.squaredNorm()));
}

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

double skirt_distance(const SkirtShape& skirt, double scale, const Eigen::Vector3d& p) {
  constexpr double rounding = 0.012;
  return capped_cone_distance(p, skirt.waist_height * scale - rounding, skirt.hem_height * scale + rounding,
                              skirt.waist_radius * scale - rounding, skirt.hem_radius * scale - rounding,
                              skirt.depth_scale) -
         rounding;
}

SkirtShape scaled(const SkirtShape& skirt, double scale) {
  SkirtShape result = skirt;
  result.waist_height *= scale;
  result.waist_radius *= scale;
  result.hem_height *= scale;
  result.hem_radius *= scale;
  return result;
}

/// Linear-blend skinning weights from the distance to each bone: bones within a few σ of the
/// nearest one share the vertex (smooth joints), the others do not touch it.
Eigen::RowVectorXd bone_weights(const Skeleton& sk, const Eigen::Vector3d& p) {
  const int n = sk.size();
  Eigen::RowVectorXd distance(n);
  for (int j = 0; j < n; ++j) distance[j] = distance_to_segment(p, sk.rest[j], sk.bone_end[j]);
  const double nearest = distance.minCoeff();
  const double sigma = 0.03 * sk.height / 1.75;
  Eigen::RowVectorXd w(n);
  for (int j = 0; j < n; ++j) {
    const double x = (distance[j] - nearest) / sigma;
    w[j] = x < 3 ? std::exp(-x * x) : 0.0;
  }
  return w / w.sum();
}

Region region_of(const Skeleton& sk, int bone, const Eigen::Vector3d& p, double garment) {
  const double s = sk.height / 1.75;
  if (garment > 0.5) return Region::skirt;
  switch (bone) {
    case head:
      return (p.y() > 1.66 * s || (p.z() < -0.02 * s && p.y() > 1.56 * s)) ? Region::hair : Region::skin;
    case neck: return Region::skin;
    case elbow_l: case elbow_r: case wrist_l: case wrist_r: return Region::skin;
    case hip_l: case hip_r: case knee_l: case knee_r: return Region::trousers;
    case ankle_l: case ankle_r: case toe_l: case toe_r: return Region::shoes;
    default: return Region::shirt;
  }
}

/// Width of the garment weight's transition from the skirt to the legs (m, at 1.75 m). The weight
/// as first defined steps from 0 to 1 within ~2.5 cm, about one template edge at 3,000 vertices, so
/// faces spanning the step (one corner on the skirt, another on a thigh) folded over their
/// neighbours: 77 % of demo's folded face pairs had a weight range above 0.3 within the pair.
/// Diffusing it roughly halves the folds per frame; the large stretches were the
/// flare's doing (deformation.cpp, membrane_fraction).
constexpr double kGarmentTransition = 0.05;

/// Diffuses `values` over the mesh's edge graph (lazy averaging with the one-ring mean), with as
/// many steps as it takes a random walk to spread about `width` at the mesh's mean edge length, so
/// the result is about the same at any vertex count. Follows the surface, unlike a Euclidean
/// blur, which would pull a hand hanging beside the skirt along with it.
Eigen::VectorXd smooth_over_surface(const core::Mesh& mesh, const Eigen::VectorXd& values, double width) {
  const long n = mesh.vertex_count();
  const auto adjacency = geometry::vertex_adjacency(mesh.F, n);
  double edge_sum = 0;
  long edge_count = 0;
  for (long v = 0; v < n; ++v)
    for (int u : adjacency[static_cast<std::size_t>(v)]) {
      if (u <= v) continue;
      edge_sum += (mesh.V.row(u) - mesh.V.row(v)).norm();
      ++edge_count;
    }
  if (edge_count == 0) return values;
  const double edge = edge_sum / static_cast<double>(edge_count);
  // Each lazy step adds about edge² / 2 to the walk's variance: σ² ≈ steps · edge² / 2.
  const int steps = std::max(1, static_cast<int>(std::lround(2.0 * (width / edge) * (width / edge))));
  Eigen::VectorXd current = values;
  Eigen::VectorXd next(n);
  for (int step = 0; step < steps; ++step) {
    for (long v = 0; v < n; ++v) {
      const auto& ring = adjacency[static_cast<std::size_t>(v)];
      if (ring.empty()) {
        next[v] = current[v];
        continue;
      }
      double mean = 0;
      for (int u : ring) mean += current[u];
      next[v] = 0.5 * current[v] + 0.5 * mean / static_cast<double>(ring.size());
    }
    current.swap(next);
  }
  return current;
}

/// Meshing costs seconds; an Actor is built more than once per process (tests, presets).
core::Mesh cached_template(const Skeleton& skeleton, const BodyOptions& options) {
  static std::mutex mutex;
  static std::map<std::tuple<double, int, int, double, double, double, double, double>, core::Mesh> cache;
  const auto& k = options.skirt;
  const auto key = std::make_tuple(options.height, options.target_vertices, options.seed, k.waist_height,
                                   k.waist_radius, k.hem_height, k.hem_radius, k.depth_scale);
  std::lock_guard lock(mutex);
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  const BodyField field(skeleton, options.skirt);
  return cache[key] = mesh_implicit_surface(field, options.target_vertices, options.seed);
}

}  // namespace

BodyField::BodyField(const Skeleton& sk, const SkirtShape& skirt_shape) {
  const double s = sk.height / 1.75;
  auto cone = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra, double rb, double depth = 1.0) {
    cones_.push_back({a, b, ra * s, rb * s, depth});
  };
  cone(sk.rest[pelvis] - Eigen::Vector3d(0, 0.03, 0) * s, sk.rest[spine], 0.135, 0.125, 0.72);
  cone(sk.rest[spine], sk.rest[chest], 0.125, 0.14, 0.72);
  cone(sk.rest[chest], sk.rest[neck] - Eigen::Vector3d(0, 0.04, 0) * s, 0.14, 0.10, 0.72);
  cone(sk.rest[neck], sk.rest[head], 0.055, 0.055);
  cone(Eigen::Vector3d(0, 1.62, 0.012) * s, Eigen::Vector3d(0, 1.655, 0.0) * s, 0.092, 0.098);
  for (int side = 0; side < 2; ++side) {
    const int c = side == 0 ? clavicle_l : clavicle_r;
    cone(sk.rest[c], sk.rest[c + 1], 0.07, 0.06);
    cone(sk.rest[c + 1], sk.rest[c + 2], 0.055, 0.042);
    cone(sk.rest[c + 2], sk.rest[c + 3], 0.040, 0.030);
    cone(sk.rest[c + 3], sk.bone_end[c + 3], 0.032, 0.024);
    const int h = side == 0 ? hip_l : hip_r;
    cone(sk.rest[h], sk.rest[h + 1], 0.085, 0.055);
    cone(sk.rest[h + 1], sk.rest[h + 2], 0.052, 0.038);
    cone(sk.rest[h + 2], sk.rest[h + 3], 0.042, 0.032);
    cone(sk.rest[h + 2], sk.rest[h + 2] + Eigen::Vector3d(0, -0.045, -0.035) * s, 0.040, 0.035);
  }
  skirt_ = scaled(skirt_shape, s);
  centre_ = sk.rest[pelvis];
  radius_ = 1.1 * sk.height;
}

double BodyField::cone_distance(const RoundCone& cone, const Eigen::Vector3d& point) const {
  // Quílez's exact round-cone distance, in a space squashed front-back by depth_scale.
  Eigen::Vector3d p = point;
  p.z() = cone.a.z() + (p.z() - cone.a.z()) / cone.depth_scale;
  const Eigen::Vector3d ba = cone.b - cone.a, pa = p - cone.a;
  const double l2 = ba.squaredNorm(), rr = cone.ra - cone.rb, a2 = l2 - rr * rr, il2 = 1.0 / l2;
  const double y = pa.dot(ba), z = y - l2;
  const double x2 = (pa * l2 - ba * y).squaredNorm(), y2 = y * y * l2, z2 = z * z * l2;
  const double k = (rr > 0 ? 1 : rr < 0 ? -1 : 0) * rr * rr * x2;
  if ((z > 0 ? 1 : -1) * a2 * z2 > k) return std::sqrt(x2 + z2) * il2 - cone.rb;
  if ((y > 0 ? 1 : -1) * a2 * y2 < k) return std::sqrt(x2 + y2) * il2 - cone.ra;
  return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - cone.ra;
}

double BodyField::operator()(const Eigen::Vector3d& p) const {
  constexpr double blend = 0.03;
  double d = skirt_distance(skirt_, 1.0, p);
  for (const auto& cone : cones_) d = smooth_min(d, cone_distance(cone, p), blend);
  return d;
}

core::Mesh mesh_implicit_surface(const BodyField& field, int target_vertices, int seed) {
  if (target_vertices < 200) throw core::bad_arguments("the body needs at least 200 vertices");
  struct Function {
    const BodyField* field;
    Traits::FT operator()(const Point& p) const { return (*field)(Eigen::Vector3d(p.x(), p.y(), p.z())); }
  };
  using Surface = CGAL::Implicit_surface_3<Traits, Function>;
  // Edge length of an equilateral mesh of the body's ~1.9 m² with target_vertices vertices.
  double edge = std::sqrt(1.9 / (0.866 * target_vertices));
  CGAL::get_default_random() = CGAL::Random(static_cast<unsigned>(seed));
  Triangulation triangulation;
  Complex complex(triangulation);
  const Eigen::Vector3d c = field.centre();
  const Surface surface(Function{&field}, Traits::Sphere_3(Point(c.x(), c.y(), c.z()), field.radius() * field.radius()),
                        1e-6);
  const double radius_bound = std::min(0.02, 0.8 * edge);
  const CGAL::Surface_mesh_default_criteria_3<Triangulation> criteria(25.0, radius_bound, 0.1 * radius_bound);
  CGAL::make_surface_mesh(complex, surface, criteria, CGAL::Manifold_tag(), 60);
  SurfaceMesh input;
  CGAL::facets_in_complex_2_to_triangle_mesh(complex, input);
  if (input.number_of_faces() == 0) throw core::internal_error("the surface mesher produced no surface");

  SurfaceMesh output;
  for (int attempt = 0; attempt < 3; ++attempt) {
    output = input;
    namespace PMP = CGAL::Polygon_mesh_processing;
    PMP::isotropic_remeshing(faces(output), edge, output, PMP::parameters::number_of_iterations(5));
    const double ratio = static_cast<double>(output.number_of_vertices()) / target_vertices;
    if (std::abs(ratio - 1.0) < 0.05) break;
    edge *= std::sqrt(ratio);
  }
  return core::copy_surface_mesh(output);
}

Body make_body(const BodyOptions& options) {
  Body body;
  body.skeleton = make_skeleton(options.height);
  const double s = options.height / 1.75;
  body.skirt = scaled(options.skirt, s);
  body.rest = cached_template(body.skeleton, options);
  const long n = body.rest.vertex_count();
  body.skin_weights.resize(n, body.skeleton.size());
  body.garment_weight.resize(n);
  body.garment_depth.resize(n);
  body.regions.resize(static_cast<std::size_t>(n));
  const auto& sk = body.skeleton;
  const double skirt_length = body.skirt.waist_height - body.skirt.hem_height;
  std::vector<Eigen::RowVectorXd> w_body(static_cast<std::size_t>(n));
  Eigen::VectorXd garment(n);
  for (long v = 0; v < n; ++v) {
    const Eigen::Vector3d p = body.rest.V.row(v).transpose();
    w_body[static_cast<std::size_t>(v)] = bone_weights(sk, p);
    // On the skirt where its own surface is closer than any limb's by ~1 cm.
    double limbs = 1e9;
    for (int j = hip_l; j < joint_count; ++j) limbs = std::min(limbs, distance_to_segment(p, sk.rest[j], sk.bone_end[j]));
    const double on_skirt = std::abs(skirt_distance(body.skirt, 1.0, p));
    const double skirt_margin = (limbs - 0.07 * s) - on_skirt;
    body.garment_depth[v] = std::clamp((body.skirt.waist_height - p.y()) / skirt_length, 0.0, 1.0);
    garment[v] = smoothstep(-0.005, 0.02, skirt_margin) * smoothstep(0.0, 0.2, body.garment_depth[v]) *
                 (1 - smoothstep(0.008 * s, 0.025 * s, on_skirt));
  }
  body.garment_weight = smooth_over_surface(body.rest, garment, kGarmentTransition * s);
  for (long v = 0; v < n; ++v) {
    const Eigen::Vector3d p = body.rest.V.row(v).transpose();
    const double g = body.garment_weight[v];
    const double depth = body.garment_depth[v];
    // The skirt hangs from the pelvis; towards the hem it partly follows the thigh on its side.
    Eigen::RowVectorXd w_skirt = Eigen::RowVectorXd::Zero(sk.size());
    const double follow = 0.45 * depth;
    const double left = smoothstep(-0.12 * s, 0.12 * s, p.x());
    w_skirt[pelvis] = 1 - follow;
    w_skirt[hip_l] = follow * left;
    w_skirt[hip_r] = follow * (1 - left);
    const auto& wb = w_body[static_cast<std::size_t>(v)];
    body.skin_weights.row(v) = (1 - g) * wb + g * w_skirt;
    int bone;
    wb.maxCoeff(&bone);
    body.regions[static_cast<std::size_t>(v)] = region_of(sk, bone, p, g);
  }
  return body;
}

}  // namespace surfcap::synth
