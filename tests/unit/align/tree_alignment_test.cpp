#include "surfcap/align/tree_alignment.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "deformable_shape.hpp"
#include "surfcap/core/mesh_io.hpp"

namespace surfcap::align {
namespace {

// A geometry-only capture of the bending test body: frame k bent by bends[k] and moved by moves[k],
// each frame reconstructed with its own connectivity (the root's coarser than the others).
struct BendingCapture {
  core::Capture capture;
  std::vector<double> bends;
  std::vector<Eigen::Vector3d> moves;

  BendingCapture(const std::string& tag, std::vector<double> frame_bends, std::vector<Eigen::Vector3d> frame_moves)
      : bends(std::move(frame_bends)), moves(std::move(frame_moves)) {
    capture.folder = std::filesystem::temp_directory_path() / ("surfcap_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(capture.folder / "s" / "mesh");
    const int count = static_cast<int>(bends.size());
    capture.sequences.push_back({"s", "s/mesh/{frame:06d}.ply", "", 0, count});
    for (int k = 0; k < count; ++k) {
      core::Mesh mesh = k == 0 ? testing::ellipsoid(18, 36) : testing::ellipsoid(23 + k % 2, 44);
      mesh.V = testing::deform_points(mesh.V, bends[static_cast<std::size_t>(k)], 0.0, moves[static_cast<std::size_t>(k)]);
      core::write_mesh(capture.mesh_path(0, k), mesh);
    }
  }
  ~BendingCapture() { std::filesystem::remove_all(capture.folder); }
};

TEST(TreeAlignment, ATwinOfTheParentsNextFrameIsAlignedFromTheMotionPrediction) {
  // Frames 0, 1, 2 bend at constant velocity (the ends move 0.32 m a frame, farther than twice the
  // coarsest patch gate); frame 3 is frame 2 a cycle later, 1.2 m farther on. The tree links 3 to 1
  // (as the tree of a cyclic motion links a frame to the one before its twin): no temporal
  // neighbour, but one step of 0 → 1's motion.
  const double b = 0.4;
  const Eigen::Vector3d still = Eigen::Vector3d::Zero(), cycle(1.2, 0.0, 0.3);
  const BendingCapture data("twin", {0.0, b, 2 * b, 2 * b + 0.002}, {still, still, still, cycle});
  similarity::FrameList frames;
  frames.sequences.push_back({"s", 0, 4});
  AlignmentTree tree;
  tree.root = 0;
  tree.nodes = {"s:0", "s:1", "s:2", "s:3"};
  tree.edges = {{0, 1, 0.0, 1}, {1, 3, 0.0, 2}, {3, 2, 0.0, 3}};
  // Similarity costs: the bend difference, so frame 3 is 500× nearer frame 2 than its parent 1.
  Eigen::MatrixXd costs(4, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) costs(i, j) = std::abs(data.bends[static_cast<std::size_t>(i)] - data.bends[static_cast<std::size_t>(j)]);
  RegisterOptions options;
  options.images = false;
  options.threads = 1;
  options.recovery.retries = 0;
  options.recovery.entry_candidates = 0;
  options.costs = &costs;
  auto align = [&](std::optional<double> twin) {
    options.motion.twin_prediction = twin;
    return register_capture(data.capture, frames, tree, options);
  };
  const Registration with = align(0.25), without = align(std::nullopt);
  const Eigen::MatrixXd& rest = with.database.template_mesh.V;
  const Eigen::MatrixXd truth = testing::deform_points(rest, 2 * b + 0.002, 0.0, cycle);
  auto rms = [&](const Registration& r) {
    return std::sqrt((r.world_positions[3] - truth).rowwise().squaredNorm().mean());
  };
  const double height = rest.col(1).maxCoeff() - rest.col(1).minCoeff();
  const Eigen::MatrixXd parent_truth = testing::deform_points(rest, b, 0.0, still);
  const Eigen::MatrixXd twin_of_next = testing::deform_points(rest, 2 * b, 0.0, still);
  ASSERT_GT(std::sqrt((parent_truth - twin_of_next).rowwise().squaredNorm().maxCoeff()),
            2 * options.pairwise.coarse_distance_height * height);
  // The parent's own error (its edge from the root has no prediction) is carried into the child.
  const double parent_rms = std::sqrt((with.world_positions[1] - parent_truth).rowwise().squaredNorm().mean());
  EXPECT_FALSE(without.frames[3].alignment.predicted);
  EXPECT_TRUE(with.frames[3].alignment.predicted);
  EXPECT_GT(with.frames[3].alignment.predicted_patches, 0);
  EXPECT_FALSE(with.frames[2].alignment.predicted) << "2 ← 3 ← 1 is no step of one motion";
  // Measured: parent 21.1 mm; the twin 31.2 mm with the prediction, 45.2 mm without (the carried
  // starts of the coarsest patches follow part of the bend from the parent's pose).
  EXPECT_GT(rms(without), 2 * parent_rms) << "from the parent's pose the ends must be out of reach";
  EXPECT_LT(rms(with), 1.6 * parent_rms) << rms(with) << " vs parent " << parent_rms;
  EXPECT_LT(rms(with), 0.75 * rms(without)) << rms(with) << " vs " << rms(without);

  // A child only somewhat nearer the parent's next frame than the parent (cost ratio 0.5) is no twin.
  costs(3, 2) = costs(2, 3) = 0.5 * costs(3, 1);
  const Registration unlike = align(0.25);
  EXPECT_FALSE(unlike.frames[3].alignment.predicted);
}

}  // namespace
}  // namespace surfcap::align
