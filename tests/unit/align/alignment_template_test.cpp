#include "surfcap/align/alignment_template.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/render/camera.hpp"
#include "test_support.hpp"

namespace surfcap::align {
namespace {

// One camera 4 m along +z looking at a unit sphere: it sees the near hemisphere up to the rim
// (z = 1/4 on the tangent cone) and nothing of the far one.
std::vector<render::Camera> front_camera() {
  return {render::look_at("front", {0, 0, 4}, Eigen::Vector3d::Zero(), {0, 1, 0}, 40.0, 640, 480)};
}

TEST(UnseenVertices, AreTheVerticesNoCameraSees) {
  const core::Mesh sphere = testing::make_sphere(24, 48);
  const std::vector<char> unseen = unseen_vertices(sphere.V, sphere.F, front_camera());
  ASSERT_EQ(unseen.size(), static_cast<std::size_t>(sphere.V.rows()));
  for (long v = 0; v < sphere.V.rows(); ++v) {
    const double z = sphere.V(v, 2);
    if (z > 0.4) EXPECT_EQ(unseen[static_cast<std::size_t>(v)], 0) << "vertex " << v;
    if (z < 0.1) EXPECT_EQ(unseen[static_cast<std::size_t>(v)], 1) << "vertex " << v;
  }
}

TEST(UnseenVertices, NothingWhenNoCameraHasTheSurfaceInItsImage) {
  const core::Mesh sphere = testing::make_sphere(24, 48);
  std::vector<render::Camera> away = front_camera();
  away[0].t += Eigen::Vector3d(100, 0, 0);  // a calibration in another frame of reference
  EXPECT_TRUE(unseen_vertices(sphere.V, sphere.F, away).empty());
  EXPECT_TRUE(unseen_vertices(sphere.V, sphere.F, {}).empty());
}

TEST(AlignmentTemplate, SoftensTheVolumeUnderWhatTheRootCamerasDoNotSee) {
  const core::Mesh sphere = testing::make_sphere(16, 32);
  const PairwiseOptions options;
  const AlignmentTemplate seen(sphere, options);
  EXPECT_EQ(seen.unseen_vertex_count(), 0);
  EXPECT_EQ(seen.deformer().softened_elements(), 0);
  TemplateSurface surface;
  surface.mesh = sphere;
  surface.observed_vertices = sphere.vertex_count();
  surface.observed_faces = sphere.face_count();
  const AlignmentTemplate half(surface, options, {}, front_camera());
  EXPECT_GT(half.unseen_vertex_count(), sphere.vertex_count() / 3);
  EXPECT_LT(half.unseen_vertex_count(), 2 * sphere.vertex_count() / 3);
  EXPECT_GT(half.deformer().softened_elements(), 0);
}

}  // namespace
}  // namespace surfcap::align
