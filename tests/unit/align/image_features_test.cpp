#include "surfcap/align/image_features.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "surfcap/align/feature_constraints.hpp"
#include "textured_capture.hpp"

namespace surfcap::align {
namespace {

class ImageFeatures : public ::testing::Test {
 protected:
  ImageFeatures() : scene_("features", 4, 480), capture_(scene_.capture), rest_(scene_.rest), frames_(scene_.frames) {}
  testing::TexturedCapture scene_;
  core::Capture& capture_;
  const core::Mesh& rest_;
  const std::vector<Eigen::MatrixXd>& frames_;
};

TEST_F(ImageFeatures, BackProjectedMatchesFollowTheTrueMotion) {
  const FeatureOptions options;
  const geometry::SurfaceQuery parent_surface(frames_[0], rest_.F), child_surface(frames_[1], rest_.F);
  const FrameFeatures parent = detect_frame_features(capture_, 0, 0, parent_surface, options);
  const FrameFeatures child = detect_frame_features(capture_, 0, 1, child_surface, options);
  ASSERT_GT(parent.size(), 200);
  ASSERT_GT(child.size(), 200);
  // Back-projected points lie on the surface they were cast onto.
  for (long i = 0; i < parent.size(); ++i)
    ASSERT_LT(parent_surface.closest_point(parent.points.row(i).transpose()).distance, 1e-6);

  const FeatureMatching matching = feature_constraints(frames_[0], rest_.F, parent, child, Eigen::Matrix3d::Identity(),
                                                       Eigen::Vector3d::Zero(), 0.01, 1.8, options);
  ASSERT_GT(matching.constraints.size(), 60u);
  std::vector<double> errors;
  for (const auto& constraint : matching.constraints) {
    Eigen::Vector3d truth = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) truth += constraint.barycentric(k) * frames_[1].row(rest_.F(constraint.face, k)).transpose();
    errors.push_back((truth - constraint.target).norm());
  }
  std::sort(errors.begin(), errors.end());
  // Pixels are ≈ 4.6 mm on the surface: matches land within a few pixels; the neighbour check
  // leaves few outliers.
  EXPECT_LT(errors[errors.size() / 2], 0.006) << "median";
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.02) << "90th percentile";

  // Deterministic, and the ratio test does reject: a stricter ratio keeps fewer matches.
  const FeatureMatching again = feature_constraints(frames_[0], rest_.F, parent, child, Eigen::Matrix3d::Identity(),
                                                    Eigen::Vector3d::Zero(), 0.01, 1.8, options);
  ASSERT_EQ(again.constraints.size(), matching.constraints.size());
  for (std::size_t k = 0; k < again.constraints.size(); ++k)
    EXPECT_EQ(again.constraints[k].target, matching.constraints[k].target);
  FeatureOptions strict = options;
  strict.ratio = 0.5;
  EXPECT_LT(feature_constraints(frames_[0], rest_.F, parent, child, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(),
                                0.01, 1.8, strict)
                .constraints.size(),
            matching.constraints.size());
}

TEST_F(ImageFeatures, NoImagesMeansNoFeaturesAndMissingOrMisfitImagesAreBadInput) {
  core::Capture without = capture_;
  without.sequences[0].images.clear();
  const geometry::SurfaceQuery surface(frames_[0], rest_.F);
  EXPECT_EQ(detect_frame_features(without, 0, 0, surface, {}).size(), 0);
  // An image of another size than its camera's is bad input naming it (SIFT crops the image to
  // where the reconstruction projects with that camera).
  core::Capture resized = capture_;
  resized.cameras[1].width /= 2;
  try {
    detect_frame_features(resized, 0, 0, surface, {});
    FAIL() << "an image of the wrong size must throw";
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(error.what()).find("cam01"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("size"), std::string::npos) << error.what();
  }
  std::filesystem::remove(capture_.image_path(0, 1, 2));
  try {
    detect_frame_features(capture_, 0, 1, surface, {});
    FAIL() << "a missing image must throw";
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(error.what()).find("cam02"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace surfcap::align
