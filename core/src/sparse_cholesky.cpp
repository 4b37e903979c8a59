#include "geobrush/sparse_cholesky.hpp"

#include <Eigen/CholmodSupport>

#include <mutex>

namespace geobrush {

struct SparseCholesky::Impl {
  Eigen::CholmodSupernodalLLT<Matrix> llt;
  // CHOLMOD's solve writes to its common workspace, which Eigen keeps inside the factor.
  mutable std::mutex solving;
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {
  // info() reports a matrix that is not positive definite; CHOLMOD would also print it.
  impl_->llt.cholmod().print = 0;
}

SparseCholesky::SparseCholesky(const Matrix& matrix) : SparseCholesky() {
  analyzePattern(matrix);
  factorize(matrix);
}

SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::analyzePattern(const Matrix& matrix) {
  impl_->llt.analyzePattern(matrix);
}

void SparseCholesky::factorize(const Matrix& matrix) {
  impl_->llt.factorize(matrix);
}

Eigen::ComputationInfo SparseCholesky::info() const {
  return impl_->llt.info();
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::Ref<const Eigen::MatrixXd>& b) const {
  const std::lock_guard lock(impl_->solving);
  return impl_->llt.solve(Eigen::MatrixXd(b));
}

Eigen::Index SparseCholesky::rows() const {
  return impl_->llt.rows();
}

}  // namespace geobrush
