#include "surfcap/geometry/gradient_operator.hpp"

#include <Eigen/Geometry>
#include <vector>

namespace surfcap::geometry {

Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const long m = F.rows();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(9 * m));
  for (long k = 0; k < m; ++k) {
    const Eigen::Vector3d p0 = V.row(F(k, 0)).transpose();
    const Eigen::Vector3d p1 = V.row(F(k, 1)).transpose();
    const Eigen::Vector3d p2 = V.row(F(k, 2)).transpose();
    const Eigen::Vector3d cross = (p1 - p0).cross(p2 - p0);
    const double double_area = cross.norm();
    if (double_area * 0.5 < 1e-20) continue;
    const Eigen::Vector3d normal = cross / double_area;
    // ∇φ_i = (n × e_i) / 2A with e_i the edge opposite vertex i (counter-clockwise).
    const Eigen::Vector3d edges[3] = {p2 - p1, p0 - p2, p1 - p0};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d gradient = normal.cross(edges[i]) / double_area;
      for (int r = 0; r < 3; ++r) entries.emplace_back(3 * k + r, F(k, i), gradient(r));
    }
  }
  Eigen::SparseMatrix<double> G(3 * m, V.rows());
  G.setFromTriplets(entries.begin(), entries.end());
  return G;
}

Eigen::SparseMatrix<double> triangle_area_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const long m = F.rows();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(3 * m));
  for (long k = 0; k < m; ++k) {
    const Eigen::Vector3d p0 = V.row(F(k, 0)).transpose();
    const Eigen::Vector3d p1 = V.row(F(k, 1)).transpose();
    const Eigen::Vector3d p2 = V.row(F(k, 2)).transpose();
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    for (int r = 0; r < 3; ++r) entries.emplace_back(3 * k + r, 3 * k + r, area);
  }
  Eigen::SparseMatrix<double> A(3 * m, 3 * m);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

Eigen::SparseMatrix<double> gradient_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const Eigen::SparseMatrix<double> G = gradient_operator(V, F);
  const Eigen::SparseMatrix<double> A = triangle_area_matrix(V, F);
  Eigen::SparseMatrix<double> L = Eigen::SparseMatrix<double>(G.transpose()) * (A * G);
  L.prune(0.0);
  return L;
}

}  // namespace surfcap::geometry
