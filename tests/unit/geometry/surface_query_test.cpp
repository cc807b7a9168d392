#include "surfcap/geometry/surface_query.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

TEST(SurfaceQuery, ClosestPointLiesOnTheSphereAndRecoversItsBarycentrics) {
  const core::Mesh sphere = testing::make_sphere(24, 48, 1.0);
  const SurfaceQuery query(sphere.V, sphere.F);
  const Eigen::Vector3d points[] = {{2, 0.3, 0.1}, {0.1, 0.2, 0.3}, {-0.5, -3, 0.2}};
  for (const auto& p : points) {
    const SurfacePoint closest = query.closest_point(p);
    ASSERT_GE(closest.face, 0);
    EXPECT_NEAR(closest.position.norm(), 1.0, 0.01);                      // on the faceted sphere
    EXPECT_GT(closest.position.normalized().dot(p.normalized()), 0.999);  // radially below p
    EXPECT_NEAR(closest.distance, (closest.position - p).norm(), 1e-12);
    const Eigen::Vector3d rebuilt = closest.barycentric(0) * sphere.V.row(sphere.F(closest.face, 0)).transpose() +
                                    closest.barycentric(1) * sphere.V.row(sphere.F(closest.face, 1)).transpose() +
                                    closest.barycentric(2) * sphere.V.row(sphere.F(closest.face, 2)).transpose();
    EXPECT_LT((rebuilt - closest.position).norm(), 1e-9);
    EXPECT_GT(query.face_normal(closest.face).dot(closest.position), 0.99);  // outward normals
  }
}

TEST(SurfaceQuery, BoundedSearchIsClosestPointWithinTheBoundAndNothingBeyond) {
  // A bumpy, unevenly tessellated surface and points inside, outside and far away.
  core::Mesh sphere = testing::make_sphere(17, 31, 1.0);
  for (long v = 0; v < sphere.V.rows(); ++v)
    sphere.V.row(v) *= 1.0 + 0.1 * std::sin(7 * sphere.V(v, 0)) * std::cos(5 * sphere.V(v, 1));
  const SurfaceQuery query(sphere.V, sphere.F);
  int found = 0, beyond = 0;
  for (int i = 0; i < 400; ++i) {
    const double t = 0.37 * i;
    const Eigen::Vector3d p = (0.2 + 0.006 * i) * Eigen::Vector3d(std::sin(t) * std::cos(2.3 * t), std::cos(t),
                                                                   std::sin(t) * std::sin(2.3 * t));
    const SurfacePoint exact = query.closest_point(p);
    for (const double bound : {0.05, 0.3, 10.0}) {
      const auto within = query.closest_point_within(p, bound);
      if (exact.distance > bound * (1 + 1e-9)) {
        EXPECT_FALSE(within.has_value()) << i;
        ++beyond;
        continue;
      }
      if (exact.distance < bound * (1 - 1e-9)) ASSERT_TRUE(within.has_value()) << i;
      if (!within) continue;
      ++found;
      EXPECT_EQ(within->face, exact.face) << i;  // bit for bit closest_point's
      EXPECT_EQ(within->distance, exact.distance) << i;
      EXPECT_TRUE(within->position == exact.position) << i;
      const Eigen::Vector3d rebuilt = within->barycentric(0) * sphere.V.row(sphere.F(within->face, 0)).transpose() +
                                      within->barycentric(1) * sphere.V.row(sphere.F(within->face, 1)).transpose() +
                                      within->barycentric(2) * sphere.V.row(sphere.F(within->face, 2)).transpose();
      EXPECT_LT((rebuilt - within->position).norm(), 1e-9) << i;
    }
  }
  EXPECT_GT(found, 400);
  EXPECT_GT(beyond, 100);
}

TEST(SurfaceQuery, ClosestPointOnATriangleInEveryVoronoiRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 1, 0);
  const auto closest = [&](const Eigen::Vector3d& p) { return closest_point_on_triangle(p, a, b, c); };
  EXPECT_LT((closest({0.5, 0.25, 3}) - Eigen::Vector3d(0.5, 0.25, 0)).norm(), 1e-15);  // face
  EXPECT_LT((closest({-1, -1, 1}) - a).norm(), 1e-15);                                 // vertices
  EXPECT_LT((closest({3, -0.5, 0}) - b).norm(), 1e-15);
  EXPECT_LT((closest({-0.5, 2, 0}) - c).norm(), 1e-15);
  EXPECT_LT((closest({1, -2, 1}) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);  // edges
  EXPECT_LT((closest({-2, 0.5, 0}) - Eigen::Vector3d(0, 0.5, 0)).norm(), 1e-15);
  // Edge b–c: the foot of the perpendicular from (1.5, 1, 0) is (1.2, 0.4, 0).
  EXPECT_LT((closest({1.5, 1, 0}) - Eigen::Vector3d(1.2, 0.4, 0)).norm(), 1e-12);
}

TEST(SurfaceQuery, RayHitsTheNearSideAndMissesWhenPointingAway) {
  const core::Mesh sphere = testing::make_sphere(24, 48, 1.0);
  const SurfaceQuery query(sphere.V, sphere.F);
  const auto hit = query.first_hit({0.05, 0.02, 5}, {0, 0, -1});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->position.z(), 1.0, 0.01);
  EXPECT_NEAR(hit->distance, 4.0, 0.01);
  EXPECT_FALSE(query.first_hit({0, 0, 5}, {0, 0, 1}).has_value());
  EXPECT_FALSE(query.first_hit({3, 0, 5}, {0, 0, -1}).has_value());
}

}  // namespace
}  // namespace surfcap::geometry
