#include "surfcap/geometry/surface_query.hpp"

#include <gtest/gtest.h>

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
