// CHOLMOD's supernodal LL^T (SuiteSparse) for sparse symmetric positive definite systems whose
// factors fill in densely, such as 2-ring (bilaplacian) operators on meshes: its dense supernode
// kernels (BLAS) factor those several times faster than Eigen's simplicial LDL^T, which stays
// faster on 1-ring (Laplacian) systems (BENCHMARKS.md, "Sparse Cholesky for the EMD envelopes").
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
