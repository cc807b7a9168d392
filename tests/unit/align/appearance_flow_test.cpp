#include "surfcap/align/appearance_flow.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "textured_capture.hpp"

namespace surfcap::align {
namespace {

class AppearanceFlow : public ::testing::Test {
 protected:
  AppearanceFlow() : scene_("flow", 4, 320) {}

  double mean_edge() const {
    double sum = 0;
    const auto& F = scene_.rest.F;
    for (long f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) sum += (scene_.rest.V.row(F(f, k)) - scene_.rest.V.row(F(f, (k + 1) % 3))).norm();
    return sum / (3.0 * static_cast<double>(F.rows()));
  }

  /// The template (the rest frame) seen by the rest frame's cameras.
  TemplateAppearance appearance(const FlowOptions& options) const {
    return TemplateAppearance(scene_.rest, capture_cameras(scene_.capture), read_grey_images(scene_.capture, 0, 0),
                              mean_edge(), options);
  }

  /// Distances of the supported targets from the true frame-1 positions, sorted.
  std::vector<double> target_errors(const FlowTargets& flow) const {
    std::vector<double> errors;
    for (long v = 0; v < flow.targets.rows(); ++v)
      if (flow.support(v) > 0) errors.push_back((flow.targets.row(v) - scene_.frames[1].row(v)).norm());
    std::sort(errors.begin(), errors.end());
    return errors;
  }

  testing::TexturedCapture scene_;
};

/// The weighted median by its definition: sort, then the first value at which the running weight
/// reaches half the total.
double sorted_weighted_median(std::vector<std::pair<double, double>> values) {
  double total = 0;
  for (const auto& value : values) total += value.second;
  std::sort(values.begin(), values.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double sum = 0;
  for (const auto& value : values) {
    sum += value.second;
    if (sum >= 0.5 * total) return value.first;
  }
  return values.back().first;
}

TEST(WeightedMedian, IsTheSortedDefinitionWithTiesAndUnevenWeights) {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> level(0, 9);  // few distinct values: many ties
  std::uniform_real_distribution<double> weight(1e-3, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 1 + trial % 37;
    std::vector<std::pair<double, double>> values;
    for (int i = 0; i < n; ++i) values.emplace_back(0.25 * level(random), trial % 3 == 0 ? 1.0 : weight(random));
    const double expected = sorted_weighted_median(values);
    std::vector<std::pair<double, double>> reordered = values;
    ASSERT_EQ(weighted_median(reordered), expected) << "trial " << trial;
  }
  // One heavy value wins whatever the others; equal halves give the lower value.
  std::vector<std::pair<double, double>> heavy{{1.0, 0.1}, {5.0, 3.0}, {-2.0, 0.1}, {9.0, 0.2}};
  EXPECT_EQ(weighted_median(heavy), 5.0);
  std::vector<std::pair<double, double>> halves{{2.0, 1.0}, {1.0, 1.0}};
  EXPECT_EQ(weighted_median(halves), 1.0);
  std::vector<std::pair<double, double>> none;
  EXPECT_TRUE(std::isnan(weighted_median(none)));
}

TEST_F(AppearanceFlow, TargetsUndoASlidingErrorOfTheEstimate) {
  const FlowOptions options;
  const TemplateAppearance root = appearance(options);
  EXPECT_GT(root.coverage(), 0.8);  // four cameras around an ellipsoid see nearly all of it
  const geometry::SurfaceQuery reconstruction(scene_.frames[1], scene_.rest.F);
  const ChildViews child(reconstruction, read_grey_images(scene_.capture, 0, 1));

  // The estimate slid 8 mm sideways and 5 mm up along the bent, twisted child surface: a pure
  // tangential error that closest-point fitting cannot see. The flow targets undo most of it.
  const Eigen::RowVector3d slide(0.008, 0.005, 0.0);
  const Eigen::MatrixXd estimate = scene_.frames[1].rowwise() + slide;
  const FlowTargets flow = flow_targets(root, estimate, scene_.rest.F, child, mean_edge(), options);
  const std::vector<double> errors = target_errors(flow);
  ASSERT_GT(static_cast<double>(errors.size()), 0.6 * static_cast<double>(estimate.rows())) << "supported vertices";
  EXPECT_GT(flow.pixels, 5000);
  const double start = slide.norm();
  std::printf("flow targets: %zu of %ld vertices, %ld pixels; error median %.2f mm, p90 %.2f mm (start %.2f mm)\n",
              errors.size(), static_cast<long>(estimate.rows()), flow.pixels, 1000 * errors[errors.size() / 2],
              1000 * errors[errors.size() * 9 / 10], 1000 * start);
  EXPECT_LT(errors[errors.size() / 2], 0.3 * start) << "median target error, start " << start;
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.6 * start) << "90th percentile";

  // From the true positions the targets stay put (within a fraction of a pixel ≈ 4 mm here).
  const FlowTargets still = flow_targets(root, scene_.frames[1], scene_.rest.F, child, mean_edge(), options);
  const std::vector<double> still_errors = target_errors(still);
  ASSERT_FALSE(still_errors.empty());
  std::printf("from the truth: median %.2f mm\n", 1000 * still_errors[still_errors.size() / 2]);
  EXPECT_LT(still_errors[still_errors.size() / 2], 0.002);

  // Deterministic.
  const FlowTargets again = flow_targets(root, estimate, scene_.rest.F, child, mean_edge(), options);
  EXPECT_EQ(again.pixels, flow.pixels);
  EXPECT_TRUE(again.targets == flow.targets);
}

TEST_F(AppearanceFlow, EachCamerasPredictionTakesThatRootCamerasOwnSample) {
  // With a headlight (the synth's, and a studio's view-dependent effects) a point's grey value
  // differs between cameras; camera c's prediction uses root camera c's sample where that camera
  // sees the point, and the cos²-weighted blend of the others elsewhere.
  const FlowOptions options;
  const std::vector<render::Camera> cameras = capture_cameras(scene_.capture);
  const std::vector<GreyImage> images = read_grey_images(scene_.capture, 0, 0);
  const TemplateAppearance all(scene_.rest, cameras, images, mean_edge(), options);
  const TemplateAppearance first(scene_.rest, {cameras[0]}, {images[0]}, mean_edge(), options);
  const Eigen::Vector3d centre = Eigen::Vector3d::Constant(1.0 / 3.0);
  long own = 0, blended = 0, differs = 0;
  for (long f = 0; f < scene_.rest.F.rows(); ++f) {
    const auto single = first.value(f, centre), preferred = all.value(f, centre, 0), blend = all.value(f, centre);
    ASSERT_EQ(preferred.has_value(), blend.has_value()) << "face " << f;
    if (single) {
      EXPECT_EQ(*preferred, *single) << "face " << f;
      ++own;
      differs += std::abs(*blend - *single) > 1e-3 ? 1 : 0;
    } else if (blend) {
      EXPECT_EQ(*preferred, *blend) << "face " << f;
      ++blended;
    }
  }
  EXPECT_GT(own, scene_.rest.F.rows() / 5);
  EXPECT_GT(blended, scene_.rest.F.rows() / 5);
  EXPECT_GT(differs, own / 2) << "the blend must differ from one camera's sample where two cameras see a point";
}

TEST_F(AppearanceFlow, NoChildImagesGiveNoTargetsAndBadImagesAreBadInput) {
  const FlowOptions options;
  const TemplateAppearance root = appearance(options);
  const geometry::SurfaceQuery reconstruction(scene_.frames[1], scene_.rest.F);
  const FlowTargets none =
      flow_targets(root, scene_.frames[1], scene_.rest.F, ChildViews(reconstruction, {}), mean_edge(), options);
  EXPECT_EQ(none.pixels, 0);
  EXPECT_EQ(none.support.maxCoeff(), 0.0);

  core::Capture without = scene_.capture;
  without.sequences[0].images.clear();
  EXPECT_TRUE(read_grey_images(without, 0, 1).empty());
  std::filesystem::remove(scene_.capture.image_path(0, 1, 1));
  try {
    read_grey_images(scene_.capture, 0, 1);
    FAIL() << "a missing image must throw";
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ExitCode::bad_input);
    EXPECT_NE(std::string(error.what()).find("cam01"), std::string::npos) << error.what();
  }
  FlowOptions bad;
  bad.stride = 0;
  EXPECT_THROW(core::validate_options(bad), core::Error);
}

}  // namespace
}  // namespace surfcap::align
