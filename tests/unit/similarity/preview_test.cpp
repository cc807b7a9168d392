// The similarity previews: what they show, and a bounded size whatever the number of frames.
#include <gtest/gtest.h>

#include "surfcap/render/png.hpp"
#include "surfcap/similarity/preview.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

/// Two sequences: 0 within a sequence, 1 across.
similarity::FloatRows two_blocks(int first, int second) {
  const int n = first + second;
  similarity::FloatRows matrix(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) matrix(i, j) = (i < first) == (j < first) ? 0.0f : 1.0f;
  return matrix;
}

TEST(SimilarityPreview, LargeMatricesAreShownAsBlockMeansAtMost2048Wide) {
  testing::TemporaryDirectory directory("similarity-preview");
  const int first = 1500, second = 1600;  // 3,100 frames: 2×2 blocks, 1,550 pixels
  const similarity::FrameIndex index({first, second});
  similarity::write_similarity_png(directory / "large.png", two_blocks(first, second), index);
  const render::Image large = render::read_png(directory / "large.png");
  EXPECT_EQ(large.width, 1550);
  EXPECT_EQ(large.height, 1550);
  // Within a sequence blue (similar), across red, the border white, at block positions.
  const Eigen::Vector3d within = large.get(100, 100), across = large.get(1400, 100);
  EXPECT_GT(within.z(), within.x() + 0.3);
  EXPECT_GT(across.x(), across.z() + 0.3);
  EXPECT_EQ(large.get(first / 2, 10), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(large.get(first / 2 - 2, 10), within);

  // Up to 2,048 frames, one pixel per frame.
  similarity::write_similarity_png(directory / "small.png", two_blocks(600, 700), similarity::FrameIndex({600, 700}));
  const render::Image small = render::read_png(directory / "small.png");
  EXPECT_EQ(small.width, 1300);
  EXPECT_EQ(small.get(600, 10), Eigen::Vector3d(1, 1, 1));
}

}  // namespace
}  // namespace surfcap
