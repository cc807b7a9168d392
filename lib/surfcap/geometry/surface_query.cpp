#include "surfcap/geometry/surface_query.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "surfcap/core/error.hpp"

namespace surfcap::geometry {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Ray = Kernel::Ray_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;

Point to_point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d to_eigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

/// CGAL's AABB traits with the closest point of a triangle by Voronoi regions
/// (closest_point_on_triangle) instead of the kernel's projection onto the supporting plane and
/// its edges: the same point to rounding, at a fraction of the cost.
struct Traits : CGAL::AABB_traits<Kernel, Primitive> {
  class Closest_point {
   public:
    Point operator()(const Point& p, const Primitive& primitive, const Point& bound) const {
      const Triangle& triangle = *primitive.id();
      const Eigen::Vector3d query = to_eigen(p);
      const Eigen::Vector3d closest =
          closest_point_on_triangle(query, to_eigen(triangle[0]), to_eigen(triangle[1]), to_eigen(triangle[2]));
      return (closest - query).squaredNorm() > CGAL::squared_distance(p, bound) ? bound : to_point(closest);
    }
  };
  Closest_point closest_point_object() const { return {}; }
};
using Tree = CGAL::AABB_tree<Traits>;

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

struct SurfaceQuery::Impl {
  std::vector<Triangle> triangles;
  std::vector<long> face_of;  ///< triangle → face index of F
  Tree tree;
};

Eigen::Vector3d barycentric_coordinates(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denominator = d00 * d11 - d01 * d01;
  if (std::abs(denominator) < 1e-300) return {1.0, 0.0, 0.0};
  const double v = (d11 * d20 - d01 * d21) / denominator;
  const double w = (d00 * d21 - d01 * d20) / denominator;
  return {1.0 - v - w, v, w};
}

SurfaceQuery::SurfaceQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
    : impl_(std::make_unique<Impl>()), V_(V), F_(F), face_normals_(F.rows(), 3) {
  impl_->triangles.reserve(static_cast<std::size_t>(F.rows()));
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double norm = n.norm();
    face_normals_.row(f) = norm > 0 ? Eigen::RowVector3d(n.transpose() / norm) : Eigen::RowVector3d::Zero();
    if (norm < 1e-20) continue;
    impl_->triangles.emplace_back(to_point(a), to_point(b), to_point(c));
    impl_->face_of.push_back(f);
  }
  if (impl_->triangles.empty()) throw core::internal_error("SurfaceQuery: the surface has no non-degenerate face");
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SurfaceQuery::~SurfaceQuery() = default;
SurfaceQuery::SurfaceQuery(SurfaceQuery&&) noexcept = default;
SurfaceQuery& SurfaceQuery::operator=(SurfaceQuery&&) noexcept = default;

SurfacePoint SurfaceQuery::surface_point(const Eigen::Vector3d& point, const Eigen::Vector3d& position,
                                         std::size_t triangle) const {
  SurfacePoint result;
  result.face = impl_->face_of[triangle];
  result.position = position;
  result.distance = (result.position - point).norm();
  result.barycentric = barycentric_coordinates(result.position, V_.row(F_(result.face, 0)),
                                               V_.row(F_(result.face, 1)), V_.row(F_(result.face, 2)));
  return result;
}

SurfacePoint SurfaceQuery::closest_point(const Eigen::Vector3d& point) const {
  const auto [closest, primitive] = impl_->tree.closest_point_and_primitive(to_point(point));
  return surface_point(point, to_eigen(closest), static_cast<std::size_t>(primitive - impl_->triangles.cbegin()));
}

std::optional<SurfacePoint> SurfaceQuery::closest_point_within(const Eigen::Vector3d& point,
                                                               double max_distance) const {
  // The tree starts from a hint and visits only boxes closer than the best point so far. With the
  // default hint (the nearest primitive reference point) closer than the bound this is exactly
  // closest_point. Otherwise the search starts from a virtual point just beyond the bound: every
  // box holding a point at the minimal distance is still visited, in the same order, so a
  // minimum within the bound comes out identical; when none is, the virtual point comes back.
  const Point query = to_point(point);
  Tree::Point_and_primitive_id hint = impl_->tree.best_hint(query);
  const double bound = max_distance * (1 + 1e-9);
  std::optional<Point> virtual_point;
  if (CGAL::squared_distance(hint.first, query) > bound * bound) {
    virtual_point = Point(point.x() + bound, point.y(), point.z());
    hint = {*virtual_point, impl_->triangles.cbegin()};
  }
  const auto [closest, primitive] = impl_->tree.closest_point_and_primitive(query, hint);
  if (virtual_point && closest == *virtual_point) return std::nullopt;
  return surface_point(point, to_eigen(closest), static_cast<std::size_t>(primitive - impl_->triangles.cbegin()));
}

std::optional<SurfacePoint> SurfaceQuery::first_hit(const Eigen::Vector3d& origin,
                                                    const Eigen::Vector3d& direction) const {
  const Ray ray(to_point(origin), to_point(origin + direction));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  const Point* point = boost::get<Point>(&hit->first);
  if (point == nullptr) return std::nullopt;  // the ray runs inside a face's plane: no single hit point
  return surface_point(origin, to_eigen(*point), static_cast<std::size_t>(hit->second - impl_->triangles.cbegin()));
}

}  // namespace surfcap::geometry
