#include "surfcap/geometry/sparse_cholesky.hpp"

#include <gtest/gtest.h>

#include "surfcap/core/error.hpp"
#include "surfcap/geometry/cotangent_laplacian.hpp"
#include "test_support.hpp"

namespace surfcap::geometry {
namespace {

Eigen::SparseMatrix<double> anchored_laplacian() {
  const core::Mesh sphere = testing::make_sphere(10, 14, 1.0);
  Eigen::SparseMatrix<double> A = cotangent_laplacian(sphere.V, sphere.F);
  A = Eigen::SparseMatrix<double>(A.transpose()) * A;
  A.coeffRef(0, 0) += 1.0;
  return A;
}

TEST(SparseCholesky, SolvesSeveralRightHandSidesWithBothBackends) {
  const Eigen::SparseMatrix<double> A = anchored_laplacian();
  const Eigen::MatrixXd X = Eigen::MatrixXd::Random(A.rows(), 4);
  const Eigen::MatrixXd B = A * X;
  for (auto backend : {SparseCholesky::Backend::automatic, SparseCholesky::Backend::simplicial_ldlt}) {
    const SparseCholesky solver(A, backend);
    EXPECT_EQ(solver.size(), A.rows());
    EXPECT_LT((solver.solve(B) - X).norm() / X.norm(), 1e-8);
  }
  EXPECT_EQ(SparseCholesky(A).backend(), SparseCholesky::Backend::cholmod);
}

TEST(SparseCholesky, RejectsIndefiniteMatrix) {
  Eigen::SparseMatrix<double> A(2, 2);
  A.insert(0, 0) = 1;
  A.insert(1, 1) = -1;
  EXPECT_THROW(SparseCholesky{A}, core::Error);
  EXPECT_THROW(SparseCholesky().solve(Eigen::MatrixXd::Zero(2, 1)), core::Error);
}

}  // namespace
}  // namespace surfcap::geometry
