#include "surfcap/learn/automatic_parts.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <deque>
#include <limits>

#include "surfcap/core/error.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/geometry/mesh_topology.hpp"

namespace surfcap::learn {

void AutomaticPartsOptions::validate() const {
  if (parts < 1) throw core::bad_arguments("--auto-parts must be ≥ 1");
  if (overlap < 0) throw core::bad_arguments("--overlap must be ≥ 0");
  if (iterations < 1) throw core::bad_arguments("k-means iterations must be ≥ 1");
}

namespace {

// Per vertex and example: the rotation of its one-ring from the template (9 numbers each).
Eigen::MatrixXd motion_features(const core::AlignedDatabase& db, const std::vector<ExampleFrame>& examples,
                                const std::vector<std::vector<int>>& adjacency, int threads) {
  const Eigen::MatrixXd& rest = db.template_mesh.V;
  const long n = rest.rows();
  Eigen::MatrixXd features(n, 9 * static_cast<Eigen::Index>(examples.size()));
  core::parallel_for(n, threads, [&](long i) {
    for (std::size_t e = 0; e < examples.size(); ++e) {
      const Eigen::MatrixXd& x = db.sequences[examples[e].sequence].frames[examples[e].frame];
      Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
      for (int j : adjacency[i]) S += (rest.row(j) - rest.row(i)).transpose() * (x.row(j) - x.row(i));
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d U = svd.matrixU();
      if ((svd.matrixV() * U.transpose()).determinant() < 0) U.col(2) = -U.col(2);
      const Eigen::Matrix3d R = svd.matrixV() * U.transpose();
      features.block(i, 9 * static_cast<Eigen::Index>(e), 1, 9) = Eigen::Map<const Eigen::RowVectorXd>(R.data(), 9);
    }
  });
  return features;
}

std::vector<int> kmeans(const Eigen::MatrixXd& X, int k, int iterations) {
  const Eigen::Index n = X.rows();
  // Farthest-point initialisation from vertex 0: deterministic and spread over the motions.
  std::vector<Eigen::Index> seeds = {0};
  Eigen::VectorXd nearest = (X.rowwise() - X.row(0)).rowwise().squaredNorm();
  while (static_cast<int>(seeds.size()) < k) {
    Eigen::Index far;
    nearest.maxCoeff(&far);
    seeds.push_back(far);
    nearest = nearest.cwiseMin((X.rowwise() - X.row(far)).rowwise().squaredNorm());
  }
  Eigen::MatrixXd centres(k, X.cols());
  for (int c = 0; c < k; ++c) centres.row(c) = X.row(seeds[c]);
  std::vector<int> label(static_cast<std::size_t>(n), 0);
  for (int it = 0; it < iterations; ++it) {
    for (Eigen::Index i = 0; i < n; ++i) (centres.rowwise() - X.row(i)).rowwise().squaredNorm().minCoeff(&label[i]);
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(k, X.cols());
    Eigen::VectorXd count = Eigen::VectorXd::Zero(k);
    for (Eigen::Index i = 0; i < n; ++i) sum.row(label[i]) += X.row(i), count[label[i]] += 1;
    for (int c = 0; c < k; ++c)
      if (count[c] > 0) centres.row(c) = sum.row(c) / count[c];
  }
  return label;
}

// Keeps each cluster's largest connected piece; other pieces join the neighbouring clusters.
void make_connected(std::vector<int>& label, const std::vector<std::vector<int>>& adjacency, int k) {
  const std::size_t n = label.size();
  std::vector<int> component(n, -1), component_label;
  std::vector<std::size_t> component_size;
  for (std::size_t s = 0; s < n; ++s) {
    if (component[s] >= 0) continue;
    const int id = static_cast<int>(component_size.size());
    std::deque<int> queue = {static_cast<int>(s)};
    component[s] = id;
    std::size_t size = 0;
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      ++size;
      for (int w : adjacency[v])
        if (component[w] < 0 && label[w] == label[s]) component[w] = id, queue.push_back(w);
    }
    component_size.push_back(size);
    component_label.push_back(label[s]);
  }
  std::vector<int> keep(static_cast<std::size_t>(k), -1);
  for (std::size_t c = 0; c < component_size.size(); ++c) {
    int& best = keep[component_label[c]];
    if (best < 0 || component_size[c] > component_size[best]) best = static_cast<int>(c);
  }
  std::deque<int> queue;
  for (std::size_t v = 0; v < n; ++v) {
    if (keep[label[v]] == component[v]) queue.push_back(static_cast<int>(v));
    else label[v] = -1;
  }
  while (!queue.empty()) {  // flood the orphans from the kept pieces
    const int v = queue.front();
    queue.pop_front();
    for (int w : adjacency[v])
      if (label[w] < 0) label[w] = label[v], queue.push_back(w);
  }
  for (int& l : label) l = std::max(l, 0);  // isolated vertices (no faces)
}

}  // namespace

PartSet automatic_parts(const core::AlignedDatabase& db, const std::vector<ExampleFrame>& examples,
                        const AutomaticPartsOptions& options) {
  options.validate();
  if (examples.empty()) throw core::bad_arguments("automatic parts need example frames");
  const long n = db.template_mesh.vertex_count();
  const auto adjacency = geometry::vertex_adjacency(db.template_mesh.F, n);
  const int k = static_cast<int>(std::min<long>(options.parts, n));
  std::vector<int> label = kmeans(motion_features(db, examples, adjacency, options.threads), k, options.iterations);
  make_connected(label, adjacency, k);
  PartSet set;
  std::vector<std::vector<int>> clusters(static_cast<std::size_t>(k));
  for (long v = 0; v < n; ++v) clusters[label[v]].push_back(static_cast<int>(v));
  // Largest cluster first (the root), ties by first vertex: deterministic names.
  std::stable_sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (const auto& cluster : clusters) {
    if (cluster.empty()) continue;
    Part part;
    part.name = "part" + std::to_string(set.parts.size());
    const auto d = geometry::edge_geodesic_distance(db.template_mesh.V, adjacency, cluster);
    for (long v = 0; v < n; ++v)
      if (d[v] <= options.overlap) part.vertices.push_back(static_cast<int>(v));
    set.parts.push_back(std::move(part));
  }
  build_hierarchy_by_sharing(set, "part0", n);
  return set;
}

}  // namespace surfcap::learn
