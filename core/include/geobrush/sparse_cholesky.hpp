// The sparse Cholesky factorization the nodes share: CHOLMOD's supernodal LL^T (SuiteSparse),
// whose dense supernode kernels (BLAS) factor the meshes' Laplacian systems several times faster
// than a simplicial factorization. Symmetric positive definite matrices only.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>

namespace geobrush {

class SparseCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<double>;

  SparseCholesky();
  // analyzePattern(matrix) then factorize(matrix).
  explicit SparseCholesky(const Matrix& matrix);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  // The fill-reducing ordering and the symbolic factor of `matrix`'s pattern (its lower triangle
  // is read), reused by every factorize() of a matrix with the same pattern.
  void analyzePattern(const Matrix& matrix);
  // Factors `matrix` numerically; info() is Eigen::NumericalIssue where it was not positive
  // definite, as Eigen's own factorizations report it.
  void factorize(const Matrix& matrix);
  Eigen::ComputationInfo info() const;

  // x with A x = b for each column of b. Safe to call from several threads on one factor
  // (CHOLMOD's workspace is guarded).
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& b) const;

  Eigen::Index rows() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace geobrush
