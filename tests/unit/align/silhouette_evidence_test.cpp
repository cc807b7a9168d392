#include "surfcap/align/silhouette_evidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "surfcap/align/pairwise_checks.hpp"
#include "surfcap/geometry/surface_query.hpp"
#include "surfcap/render/camera.hpp"
#include "test_support.hpp"

namespace surfcap::align {
namespace {

// A unit sphere seen by four cameras on a ring of radius 4 (along ±x and ±z): each sees it within
// 14.48° of its axis (asin 1/4). Its visual hull bulges towards the diagonals between cameras: in
// the horizontal plane at 45° it reaches 1.16 from the centre.
constexpr double kGate = 0.05;

std::vector<render::Camera> four_cameras() {
  return render::ring_cameras(4, 4.0, 0.0, Eigen::Vector3d::Zero(), 40.0, 640, 480);
}

/// A point at `radius` from the centre in the horizontal plane, `degrees` from +x towards +z.
Eigen::Vector3d at(double radius, double degrees) {
  const double a = degrees * M_PI / 180;
  return {radius * std::cos(a), 0.0, radius * std::sin(a)};
}

TEST(SilhouetteEvidence, APointOutsideACamerasSilhouetteIsEvidenceAndPhantomVolumeIsNot) {
  const core::Mesh sphere = testing::make_sphere(48, 96);
  const SilhouetteEvidence evidence(four_cameras(), sphere.V, sphere.F, kGate);
  // On the x axis at 1.12: the cameras on ±z see it 0.087 beyond the silhouette's rim (x = 1.033
  // at its depth), more than the gate.
  EXPECT_TRUE(evidence.outside(at(1.12, 0)));
  // At 45°, 1.12 from the centre (0.12 from the sphere): inside every camera's silhouette, in the
  // visual hull's phantom volume.
  EXPECT_FALSE(evidence.outside(at(1.12, 45)));
  // Beyond the visual hull's bulge at 45°: the cameras see it outside.
  EXPECT_TRUE(evidence.outside(at(1.35, 45)));
  // Within the gate of the sphere: never evidence.
  EXPECT_FALSE(evidence.outside(at(1.03, 0)));
  EXPECT_FALSE(evidence.outside(Eigen::Vector3d::Zero()));
}

TEST(SilhouetteEvidence, ACameraThatDoesNotSeeThePointTellsNothing) {
  const core::Mesh sphere = testing::make_sphere(48, 96);
  // Only the camera on +z (its image spans ±1.5 m at the centre's depth): a point beside the
  // sphere in its image is evidence; one outside its image or behind it is not.
  const std::vector<render::Camera> one{four_cameras()[0]};
  ASSERT_GT(one[0].centre().z(), 3.9);
  const SilhouetteEvidence evidence(one, sphere.V, sphere.F, kGate);
  EXPECT_TRUE(evidence.outside({1.3, 0.0, 0.0}));
  EXPECT_FALSE(evidence.outside({6.0, 0.0, 0.0}));
  EXPECT_FALSE(evidence.outside({0.0, 0.0, 5.0}));
}

TEST(SilhouetteEvidence, CamerasThatSeeNoneOfTheSurfaceTellNothing) {
  // The ring moved 100 m away (a calibration in another frame of reference): no camera has the
  // sphere in its image, so every point far from it counts, phantom bulge included.
  const core::Mesh sphere = testing::make_sphere(48, 96);
  std::vector<render::Camera> away = four_cameras();
  for (render::Camera& camera : away) camera.t += Eigen::Vector3d(100, 0, 0);
  const SilhouetteEvidence evidence(away, sphere.V, sphere.F, kGate);
  EXPECT_TRUE(evidence.outside(at(1.12, 45)));
  EXPECT_TRUE(evidence.outside(at(1.12, 0)));
}

TEST(SilhouetteEvidence, TheUncoveredCheckCountsOnlyWhatSomeCameraShows) {
  const core::Mesh sphere = testing::make_sphere(48, 96);
  // The reconstruction: two small triangles 0.12 off the sphere, one in the visual hull's phantom
  // volume (45°), one where the cameras on ±z see it outside the sphere (on the x axis).
  Eigen::MatrixXd V(6, 3);
  Eigen::MatrixXi F(2, 3);
  for (int t = 0; t < 2; ++t) {
    const Eigen::Vector3d c = at(1.12, t == 0 ? 45 : 0);
    V.row(3 * t) = (c + Eigen::Vector3d(0, 0.002, 0)).transpose();
    V.row(3 * t + 1) = (c + Eigen::Vector3d(0, -0.002, 0.002)).transpose();
    V.row(3 * t + 2) = (c + Eigen::Vector3d(0, -0.002, -0.002)).transpose();
    F.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
  }
  const geometry::SurfaceQuery reconstruction(V, F);
  const std::vector<render::Camera> cameras = four_cameras();
  EXPECT_DOUBLE_EQ(uncovered_fraction(reconstruction, sphere.V, sphere.F, kGate), 1.0);
  EXPECT_DOUBLE_EQ(uncovered_fraction(reconstruction, sphere.V, sphere.F, kGate, nullptr, &cameras), 0.5);
  const std::vector<render::Camera> none;
  EXPECT_DOUBLE_EQ(uncovered_fraction(reconstruction, sphere.V, sphere.F, kGate, nullptr, &none), 1.0);
}

}  // namespace
}  // namespace surfcap::align
