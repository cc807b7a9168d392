#include "surfcap/geometry/sparse_cholesky.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <optional>
#include <vector>

#include "surfcap/core/error.hpp"

namespace surfcap::geometry {

struct SparseCholesky::Impl {
  long n = 0;
  Backend backend = Backend::cholmod;
  Backend requested = Backend::automatic;
  std::optional<Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>> cholmod;
  std::optional<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>> ldlt;
  std::vector<int> outer, inner;  ///< the pattern analysed

  bool same_pattern(const Eigen::SparseMatrix<double>& A) const {
    if (A.rows() != n || !A.isCompressed() || static_cast<std::size_t>(A.nonZeros()) != inner.size()) return false;
    return std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1, outer.begin()) &&
           std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), inner.begin());
  }
  void keep_pattern(const Eigen::SparseMatrix<double>& A) {
    if (!A.isCompressed()) return;
    outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
    inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  }
};

SparseCholesky::SparseCholesky() = default;
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

SparseCholesky::SparseCholesky(const Eigen::SparseMatrix<double>& A, Backend backend)
    : impl_(std::make_unique<Impl>()) {
  if (A.rows() != A.cols()) throw core::internal_error("SparseCholesky: matrix is not square");
  impl_->n = A.rows();
  impl_->requested = backend;
  if (backend != Backend::simplicial_ldlt) {
    impl_->cholmod.emplace();
    // LLᵀ (not CHOLMOD's automatic LDLᵀ for small matrices), so an indefinite matrix fails.
    impl_->cholmod->setMode(Eigen::CholmodSupernodalLLt);
    impl_->cholmod->compute(A);
    if (impl_->cholmod->info() == Eigen::Success) {
      impl_->backend = Backend::cholmod;
      impl_->keep_pattern(A);
      return;
    }
    impl_->cholmod.reset();
    if (backend == Backend::cholmod)
      throw core::internal_error("SparseCholesky: CHOLMOD factorisation failed (matrix not positive definite?)");
  }
  impl_->ldlt.emplace(A);
  impl_->backend = Backend::simplicial_ldlt;
  if (impl_->ldlt->info() != Eigen::Success || (impl_->ldlt->vectorD().array() <= 0).any())
    throw core::internal_error("SparseCholesky: factorisation failed (matrix not positive definite)");
  impl_->keep_pattern(A);
}

void SparseCholesky::refactor(const Eigen::SparseMatrix<double>& A) {
  if (!impl_ || !impl_->same_pattern(A)) {
    *this = SparseCholesky(A, impl_ ? impl_->requested : Backend::automatic);
    return;
  }
  if (impl_->cholmod) {
    impl_->cholmod->factorize(A);
    if (impl_->cholmod->info() == Eigen::Success) return;
    // Not positive definite with this pattern's analysis: start again (the fallback decides).
    *this = SparseCholesky(A, impl_->requested);
    return;
  }
  impl_->ldlt->factorize(A);
  if (impl_->ldlt->info() != Eigen::Success || (impl_->ldlt->vectorD().array() <= 0).any())
    throw core::internal_error("SparseCholesky: factorisation failed (matrix not positive definite)");
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
  if (!impl_) throw core::internal_error("SparseCholesky::solve before factorisation");
  if (B.rows() != impl_->n) throw core::internal_error("SparseCholesky::solve: right-hand side has wrong size");
  if (B.cols() == 0) return B;
  if (impl_->cholmod) return impl_->cholmod->solve(B);
  return impl_->ldlt->solve(B);
}

long SparseCholesky::size() const { return impl_ ? impl_->n : 0; }
SparseCholesky::Backend SparseCholesky::backend() const {
  return impl_ ? impl_->backend : Backend::automatic;
}

}  // namespace surfcap::geometry
