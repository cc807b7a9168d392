#include "surfcap/geometry/surface_query.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
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
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d to_eigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

/// Bounding-volume hierarchy over triangles for closest-point searches: median splits along the
/// longest axis of the centroids, leaves of at most 4 triangles.
class TriangleHierarchy {
 public:
  void build(std::vector<std::array<Eigen::Vector3d, 3>> corners) {
    corners_ = std::move(corners);
    order_.resize(corners_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
    nodes_.clear();
    nodes_.reserve(2 * corners_.size() / 4 + 8);
    if (!corners_.empty()) split(0, static_cast<int>(corners_.size()));
  }

  /// The triangle (index into the corners) with the closest point to p at a squared distance of at
  /// most `bound2`, and that point; -1 when none.
  int closest(const Eigen::Vector3d& p, double bound2, Eigen::Vector3d& best_point) const {
    int best = -1;
    double best2 = bound2;
    if (nodes_.empty() || nodes_[0].box.squaredExteriorDistance(p) > best2) return best;
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
      if (node.box.squaredExteriorDistance(p) > best2) continue;
      if (node.left < 0) {
        for (int k = node.first; k < node.first + node.count; ++k) {
          const auto& t = corners_[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])];
          const Eigen::Vector3d q = closest_point_on_triangle(p, t[0], t[1], t[2]);
          const double d2 = (q - p).squaredNorm();
          if (d2 < best2 || (best < 0 && d2 <= best2)) {
            best2 = d2;
            best = order_[static_cast<std::size_t>(k)];
            best_point = q;
          }
        }
        continue;
      }
      const double left = nodes_[static_cast<std::size_t>(node.left)].box.squaredExteriorDistance(p);
      const double right = nodes_[static_cast<std::size_t>(node.right)].box.squaredExteriorDistance(p);
      // The nearer child is visited first (pushed last); a box beyond the best so far is skipped.
      const bool left_first = left <= right;
      const int first = left_first ? node.left : node.right, second = left_first ? node.right : node.left;
      const double first2 = left_first ? left : right, second2 = left_first ? right : left;
      if (second2 <= best2 && top < static_cast<int>(stack.size())) stack[top++] = second;
      if (first2 <= best2 && top < static_cast<int>(stack.size())) stack[top++] = first;
    }
    return best;
  }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  ///< children (−1: a leaf of order_[first, first + count))
    int first = 0, count = 0;
  };

  int split(int first, int count) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Eigen::AlignedBox3d box, centres;
    for (int k = first; k < first + count; ++k) {
      const auto& t = corners_[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])];
      for (const auto& corner : t) box.extend(corner);
      centres.extend((t[0] + t[1] + t[2]) / 3.0);
    }
    nodes_[static_cast<std::size_t>(index)].box = box;
    nodes_[static_cast<std::size_t>(index)].first = first;
    nodes_[static_cast<std::size_t>(index)].count = count;
    if (count <= 4) return index;
    int axis = 0;
    centres.sizes().maxCoeff(&axis);
    const auto centre = [&](int i) {
      const auto& t = corners_[static_cast<std::size_t>(i)];
      return t[0](axis) + t[1](axis) + t[2](axis);
    };
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](int a, int b) { return centre(a) < centre(b) || (centre(a) == centre(b) && a < b); });
    const int left = split(first, half);
    const int right = split(first + half, count - half);
    nodes_[static_cast<std::size_t>(index)].left = left;
    nodes_[static_cast<std::size_t>(index)].right = right;
    return index;
  }

  std::vector<std::array<Eigen::Vector3d, 3>> corners_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace

struct SurfaceQuery::Impl {
  std::vector<Triangle> triangles;
  std::vector<long> face_of;  ///< triangle → face index of F
  Tree tree;
  TriangleHierarchy hierarchy;  ///< the same triangles (closest_point_within)
};

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
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  corners.reserve(impl_->face_of.size());
  for (const long f : impl_->face_of)
    corners.push_back({V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(), V.row(F(f, 2)).transpose()});
  impl_->hierarchy.build(std::move(corners));
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
  Eigen::Vector3d position;
  const double bound2 = max_distance * max_distance;
  const int triangle = impl_->hierarchy.closest(point, std::isnan(bound2) ? 0.0 : bound2, position);
  if (triangle < 0) return std::nullopt;
  return surface_point(point, position, static_cast<std::size_t>(triangle));
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
