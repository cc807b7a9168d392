#include "surfcap/geometry/mean_edge_length.hpp"

namespace surfcap::geometry {

double mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double sum = 0;
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) sum += (V.row(F(f, k)) - V.row(F(f, (k + 1) % 3))).norm();
  return F.rows() > 0 ? sum / (3.0 * static_cast<double>(F.rows())) : 0.0;
}

}  // namespace surfcap::geometry
