// The target cage C_t by Laplacian editing of the source cage C_s (GeoBrush,
// Takayama et al. 2011, section 4.3, Eq. 2; Laplacian editing after
// Sorkine et al. 2004): min |L w - delta|^2 with delta = lambda T L(C_s),
// T the change from the source to the target local frame at each cage column.
#pragma once

#include <Eigen/SparseCholesky>
#include <memory>
#include <stdexcept>

#include "geobrush/canvas.hpp"

namespace geobrush {

struct CageFitOptions {
  // Weight of the boundary-midpoint constraints against the Laplacians.
  double constraintWeight = 10.0;
};

class CageFitError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The factorization depends only on the cage's connectivity and the weight,
// so it is made once and reused while the target canvas moves.
class CageFitSolver {
 public:
  CageFitSolver(const Cage& source, double constraintWeight);
  bool fits(const Cage& source, double constraintWeight) const;

  const Eigen::SparseMatrix<double>& laplacian() const { return laplacian_; }
  const std::vector<int>& constrainedColumns() const { return boundaryColumns_; }
  double weight() const { return weight_; }
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& deltas, const Eigen::MatrixX3d& midpoints) const;

 private:
  std::size_t vertices_ = 0;
  std::size_t faces_ = 0;
  double weight_ = 0;
  std::vector<int> top_, bottom_;
  std::vector<int> boundaryColumns_;  // domain vertices on C's boundary
  Eigen::SparseMatrix<double> laplacian_;
  Eigen::SparseMatrix<double> constraints_;  // rows: (top + bottom) / 2 of each boundary column
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor_;
};

// E_s^-1(u) and the source frame at each cage column's u: they depend only on the source cage and
// parameterization, so they are found once and reused while the target canvas moves.
struct SourceColumns {
  SourceColumns(const Cage& sourceCage, const Parameterization& source);
  std::vector<Eigen::Vector3d> point;
  std::vector<Eigen::Matrix3d> frame;  // columns: u axis, v axis, normal
};

struct CageFitResult {
  Cage cage;
  // Domain vertices of C that lie outside the target parameterization's
  // triangles (their frames and positions were extrapolated).
  std::size_t columnsOutsideTarget = 0;
};

// `source` is the parameterization the source cage was built on; `target`
// lives in the same parameter domain. A reusable `solver` (made for this
// cage and weight) skips the factorization, and `columns` (made for this cage
// and source) the search of the source canvas.
CageFitResult fitCage(const Cage& sourceCage, const Parameterization& source,
                      const Parameterization& target, const CageFitOptions& options = {},
                      const CageFitSolver* solver = nullptr,
                      const SourceColumns* columns = nullptr);

}  // namespace geobrush
