#include "surfcap/geometry/cotangent_laplacian.hpp"

#include <Eigen/Geometry>
#include <vector>

namespace surfcap::geometry {

Eigen::SparseMatrix<double> cotangent_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(F.rows()) * 12);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d p[3] = {V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(),
                                  V.row(F(f, 2)).transpose()};
    const double double_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (double_area < 2e-20) continue;
    for (int k = 0; k < 3; ++k) {
      // The angle at corner k faces the edge (k+1, k+2): cot = (a·b) / |a×b|.
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const double cot = (p[i] - p[k]).dot(p[j] - p[k]) / double_area;
      const double w = 0.5 * cot;
      const int vi = F(f, i), vj = F(f, j);
      entries.emplace_back(vi, vj, -w);
      entries.emplace_back(vj, vi, -w);
      entries.emplace_back(vi, vi, w);
      entries.emplace_back(vj, vj, w);
    }
  }
  Eigen::SparseMatrix<double> L(V.rows(), V.rows());
  L.setFromTriplets(entries.begin(), entries.end());
  L.makeCompressed();
  return L;
}

}  // namespace surfcap::geometry
