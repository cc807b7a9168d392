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

TEST(SparseCholesky, RefactoringWithThePatternAnalysedGivesTheFreshFactorBitForBit) {
  const Eigen::SparseMatrix<double> A = anchored_laplacian();
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
  for (auto backend : {SparseCholesky::Backend::automatic, SparseCholesky::Backend::simplicial_ldlt}) {
    SparseCholesky solver(A, backend);
    for (int k = 1; k <= 3; ++k) {
      // Other values on the same pattern: the symbolic analysis is reused.
      Eigen::SparseMatrix<double> C = A;
      for (long i = 0; i < C.rows(); i += k + 1) C.coeffRef(i, i) += 0.5 * k;
      C.makeCompressed();
      solver.refactor(C);
      const Eigen::MatrixXd fresh = SparseCholesky(C, backend).solve(B), reused = solver.solve(B);
      EXPECT_EQ(solver.backend(), SparseCholesky(C, backend).backend());
      EXPECT_TRUE((fresh.array() == reused.array()).all()) << k;
      EXPECT_LT((C * reused - B).norm() / B.norm(), 1e-9);
    }
  }
  // Another pattern: factored from scratch.
  SparseCholesky solver(A);
  Eigen::SparseMatrix<double> D = A;
  D.coeffRef(0, A.rows() - 1) += 1e-3;
  D.coeffRef(A.rows() - 1, 0) += 1e-3;
  D.makeCompressed();
  solver.refactor(D);
  EXPECT_LT((D * solver.solve(B) - B).norm() / B.norm(), 1e-9);
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
