#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <numeric>
#include <set>
#include <tuple>
#include <random>

#include <Eigen/Geometry>
#include <algorithm>

#include "surfcap/similarity/similarity_files.hpp"
#include "surfcap/similarity/similarity_matrix.hpp"
#include "surfcap/similarity/spanning_tree.hpp"

namespace surfcap {
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd line_costs(const std::vector<double>& x) {
  const long n = static_cast<long>(x.size());
  Eigen::MatrixXd costs(n, n);
  for (long i = 0; i < n; ++i)
    for (long j = 0; j < n; ++j) costs(i, j) = std::abs(x[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(j)]);
  return costs;
}

/// Σ over nodes of the path cost from `root`, by brute force.
double weighted_depth(const similarity::SimilarityTree& tree, int n, int root) {
  std::vector<std::vector<std::pair<int, double>>> adjacency(static_cast<std::size_t>(n));
  for (const auto& e : tree.edges) {
    adjacency[static_cast<std::size_t>(e.parent)].push_back({e.child, e.cost});
    adjacency[static_cast<std::size_t>(e.child)].push_back({e.parent, e.cost});
  }
  std::vector<double> distance(static_cast<std::size_t>(n), -1);
  std::vector<int> stack{root};
  distance[static_cast<std::size_t>(root)] = 0;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (const auto& [w, c] : adjacency[static_cast<std::size_t>(v)])
      if (distance[static_cast<std::size_t>(w)] < 0) {
        distance[static_cast<std::size_t>(w)] = distance[static_cast<std::size_t>(v)] + c;
        stack.push_back(w);
      }
  }
  double total = 0;
  for (double d : distance) total += d;
  return total;
}

TEST(SpanningTree, ChainOfFramesOnALine) {
  const std::vector<double> x = {0.0, 1.0, 2.5, 2.9, 4.0, 7.0};
  const auto tree = similarity::similarity_tree(line_costs(x));
  ASSERT_EQ(tree.edges.size(), x.size() - 1);
  EXPECT_NEAR(tree.total_cost, 7.0, 1e-12);
  EXPECT_DOUBLE_EQ(tree.threshold, 3.0);  // frame 5's best match is 3 away
  EXPECT_EQ(tree.components_after_pruning, 1);
  // Breadth-first: every parent is the root or an earlier child.
  std::vector<char> reached(x.size(), 0);
  reached[static_cast<std::size_t>(tree.root)] = 1;
  for (const auto& e : tree.edges) {
    EXPECT_TRUE(reached[static_cast<std::size_t>(e.parent)]);
    reached[static_cast<std::size_t>(e.child)] = 1;
  }
}

TEST(SpanningTree, RootMinimisesWeightedDepth) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0, 10);
  std::vector<double> x(40);
  for (auto& value : x) value = uniform(random);
  const auto tree = similarity::similarity_tree(line_costs(x));
  const double chosen = weighted_depth(tree, 40, tree.root);
  EXPECT_NEAR(chosen, tree.weighted_depth, 1e-9);
  for (int r = 0; r < 40; ++r) EXPECT_LE(chosen, weighted_depth(tree, 40, r) + 1e-9);
  const auto forced = similarity::similarity_tree(line_costs(x), 3);
  EXPECT_EQ(forced.root, 3);
}

TEST(SpanningTree, AutomaticRootIsTheShallowestOfTheEligibleFrames) {
  // Frames on a line: unrestricted, the optimal root is central; restricted to the frames of the
  // widest stance, it is the eligible frame of least weighted depth, which is not the global optimum.
  std::vector<double> x(21);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i);
  const auto free_tree = similarity::similarity_tree(line_costs(x));
  EXPECT_EQ(free_tree.root, 10);
  std::vector<double> stance(x.size(), 0.1);
  stance[2] = 0.5;   // the widest, far from the centre
  stance[7] = 0.45;  // nearer the centre
  stance[15] = 0.3;  // farther than frame 7
  const std::vector<bool> eligible = similarity::wide_stance_roots(stance, 0.1);  // the ceil(2.1) = 3 widest
  ASSERT_EQ(eligible.size(), x.size());
  EXPECT_TRUE(eligible[2] && eligible[7] && eligible[15]);
  EXPECT_EQ(std::count(eligible.begin(), eligible.end(), true), 3);
  const auto tree = similarity::similarity_tree(line_costs(x), std::nullopt, std::nullopt, eligible);
  EXPECT_EQ(tree.root, 7);
  EXPECT_NEAR(tree.weighted_depth, weighted_depth(tree, 21, 7), 1e-9);
  EXPECT_GT(tree.weighted_depth, free_tree.weighted_depth);
  // Ties at the limit are all kept; an empty stance list means no restriction.
  const std::vector<bool> all = similarity::wide_stance_roots(std::vector<double>(5, 0.2), 0.25);
  EXPECT_EQ(std::count(all.begin(), all.end(), true), 5);
  EXPECT_TRUE(similarity::wide_stance_roots({}, 0.25).empty());
  EXPECT_EQ(similarity::similarity_tree(line_costs(x), std::nullopt, std::nullopt, {}).root, 10);
  // A given root wins over the eligibility.
  EXPECT_EQ(similarity::similarity_tree(line_costs(x), 3, std::nullopt, eligible).root, 3);
}

TEST(SpanningTree, StanceWidthIsTheFeetSpreadOverTheHeightInAnyHeading) {
  // A 1.75 m column (the body) standing on two feet 0.6 m apart: stance 0.6 / 1.75 whichever way the
  // feet line points; feet together → only the feet's own width.
  auto body = [](double apart, double heading) {
    core::Mesh mesh;
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i <= 70; ++i) points.emplace_back(0.0, 0.1 + 1.65 * i / 70.0, 0.0);
    for (int side : {-1, 1})
      for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 4; ++j)
          for (int k = 0; k <= 4; ++k) points.emplace_back(side * apart / 2 + 0.01 * (j - 2), 0.01 * i, 0.02 * (k - 2));
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix();
    mesh.V.resize(static_cast<long>(points.size()), 3);
    for (std::size_t k = 0; k < points.size(); ++k) mesh.V.row(static_cast<long>(k)) = (turn * points[k]).transpose();
    return mesh;
  };
  EXPECT_NEAR(similarity::stance_width(body(0.6, 0.0)), (0.6 + 0.04) / 1.75, 1e-9);
  EXPECT_NEAR(similarity::stance_width(body(0.6, 1.1)), (0.6 + 0.04) / 1.75, 1e-9);
  EXPECT_LT(similarity::stance_width(body(0.0, 0.4)), 0.1 / 1.75);
}

TEST(SpanningTree, DisconnectedByPruningIsJoinedAndReported) {
  Eigen::MatrixXd costs(4, 4);
  costs << 0, 1, 10, 12, 1, 0, 11, 10, 10, 11, 0, 1, 12, 10, 1, 0;
  const auto tree = similarity::similarity_tree(costs);
  EXPECT_EQ(tree.components_after_pruning, 2);
  EXPECT_EQ(tree.joining_edges, 1);
  EXPECT_EQ(tree.edges.size(), 3u);
  EXPECT_NEAR(tree.total_cost, similarity::minimum_spanning_tree_cost(costs), 1e-12);
}

TEST(SimilarityMatrix, ShardedRowsEqualTheWholeMatrixByteForByte) {
  similarity::ShapeHistogramOptions layout;
  layout.shells = 2;
  layout.elevation_bins = 2;
  layout.azimuth_order = 3;
  const similarity::FrameIndex index({5, 3, 6});
  std::mt19937 random(3);
  std::normal_distribution<float> normal;
  RowMatrix histograms(index.frames(), layout.size());
  for (long i = 0; i < histograms.size(); ++i) histograms.data()[i] = normal(random);
  similarity::SimilarityOptions options;
  options.threads = 1;
  const RowMatrix whole = similarity::similarity_rows(histograms, layout, index, 0, index.frames(), options);
  options.threads = 3;
  RowMatrix joined(index.frames(), index.frames());
  for (const auto [begin, end] : {std::pair{0L, 4L}, std::pair{4L, 9L}, std::pair{9L, 14L}})
    joined.middleRows(begin, end - begin) = similarity::similarity_rows(histograms, layout, index, begin, end, options);
  EXPECT_EQ(std::memcmp(whole.data(), joined.data(), sizeof(float) * static_cast<std::size_t>(whole.size())), 0);
  // Temporal filter, clipped: frame 5 (first of sequence 1) vs frame 0 (first of sequence 0)
  // averages k = 0..2 only.
  auto d = [&](long i, long j) {
    return similarity::match_histograms(histograms.row(i).data(), histograms.row(j).data(), layout).distance;
  };
  EXPECT_NEAR(whole(5, 0), (d(5, 0) + d(6, 1) + d(7, 2)) / 3.0, 1e-5);
  // Frame 7 (last of sequence 1) vs frame 2: k = -2..0.
  EXPECT_NEAR(whole(7, 2), (d(5, 0) + d(6, 1) + d(7, 2)) / 3.0, 1e-5);
  EXPECT_EQ(whole(4, 4), 0.0f);
}

/// Kruskal's tree over every edge in (cost, a, b) order: the reference the dense tree must equal.
std::set<std::pair<int, int>> kruskal_reference(const Eigen::MatrixXd& costs, double threshold, int& kept) {
  const int n = static_cast<int>(costs.rows());
  std::vector<std::tuple<double, int, int>> edges;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) edges.emplace_back(0.5 * (costs(i, j) + costs(j, i)), i, j);
  std::sort(edges.begin(), edges.end());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) { return parent[static_cast<std::size_t>(x)] == x ? x : find(parent[static_cast<std::size_t>(x)]); };
  std::set<std::pair<int, int>> tree;
  kept = 0;
  for (const auto& [cost, a, b] : edges)
    if (find(a) != find(b)) {
      parent[static_cast<std::size_t>(find(a))] = find(b);
      tree.insert({a, b});
      kept += cost <= threshold;
    }
  return tree;
}

TEST(SpanningTree, DenseTreeIsKruskalsWithTiesAndTheSameFromFloatCosts) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> level(1, 6);  // few distinct costs: many ties
  const int n = 60;
  RowMatrix stored(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) stored(i, j) = i == j ? 0.0f : 0.125f * static_cast<float>(level(random));
  const Eigen::MatrixXd costs = stored.cast<double>();
  const auto from_double = similarity::similarity_tree(costs);
  const auto from_float = similarity::similarity_tree(stored);
  int kept = 0;
  const auto reference = kruskal_reference(costs, from_double.threshold, kept);
  std::set<std::pair<int, int>> edges;
  for (const auto& e : from_double.edges) edges.insert({std::min(e.parent, e.child), std::max(e.parent, e.child)});
  EXPECT_EQ(edges, reference);
  EXPECT_EQ(from_double.components_after_pruning, n - kept);
  EXPECT_EQ(from_double.joining_edges, from_double.components_after_pruning > 1 ? n - 1 - kept : 0);
  EXPECT_EQ(from_double.threshold, similarity::automatic_threshold(stored));
  ASSERT_EQ(from_float.edges.size(), from_double.edges.size());
  for (std::size_t e = 0; e < from_float.edges.size(); ++e) {
    EXPECT_EQ(from_float.edges[e].parent, from_double.edges[e].parent);
    EXPECT_EQ(from_float.edges[e].child, from_double.edges[e].child);
  }
  EXPECT_EQ(from_float.root, from_double.root);
  EXPECT_EQ(from_float.total_cost, from_double.total_cost);
  EXPECT_EQ(from_float.weighted_depth, from_double.weighted_depth);
}

}  // namespace
}  // namespace surfcap
