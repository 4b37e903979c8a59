// The exact reference for the offset membrane (GeoBrush paper section 4.4, Eq. 4): the same
// discrete system as solveMembrane, assembled and factored by a sparse LDL^T.
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <stdexcept>

#include "membrane.hpp"
#include "membrane_levels.hpp"

namespace geobrush {

MembraneDirectResult solveMembraneDirect(const MembraneProblem& problem) {
  const std::vector<MembraneNode> roles = membrane_detail::validateProblem(problem);
  const membrane_detail::Level finest = membrane_detail::finestLevel(
      problem.width, problem.height, problem.inside, problem.continuity, 0);

  const auto n = Eigen::Index(finest.unknowns.size());
  std::vector<int> position(finest.grid.size(), -1);
  for (Eigen::Index i = 0; i < n; ++i)
    position[std::size_t(finest.unknowns[std::size_t(i)])] = int(i);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(n) * 13);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < membrane_detail::kSlots; ++k) {
      const double weight = finest.regular[std::size_t(k)];
      const int node = finest.unknowns[std::size_t(i)] + finest.slotOffsets[std::size_t(k)];
      if (const int j = position[std::size_t(node)]; weight != 0 && j >= 0)
        entries.emplace_back(i, j, weight);
    }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());

  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factorization(matrix);
  if (factorization.info() != Eigen::Success)
    throw std::runtime_error("membrane: the sparse LDL^T factorization failed");

  MembraneDirectResult result;
  for (const std::vector<double>& field : problem.channels) {
    const std::vector<double> b = membrane_detail::rightHandSide(
        finest, membrane_detail::padded(finest.grid, field, roles, MembraneNode::Fixed));
    Eigen::VectorXd rhs(n);
    for (Eigen::Index i = 0; i < n; ++i)
      rhs[i] = b[std::size_t(finest.unknowns[std::size_t(i)])];
    const Eigen::VectorXd solution = factorization.solve(rhs);
    if (factorization.info() != Eigen::Success)
      throw std::runtime_error("membrane: the sparse LDL^T solve failed");
    const double bNorm = rhs.norm();
    const double rNorm = (rhs - matrix * solution).norm();
    result.residual = std::max(result.residual, bNorm > 0 ? rNorm / bNorm : rNorm);
    std::vector<double> values = field;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int node = finest.unknowns[std::size_t(i)];
      const int x = node % finest.grid.stride() - membrane_detail::kPad;
      const int y = node / finest.grid.stride() - membrane_detail::kPad;
      values[std::size_t(y) * std::size_t(problem.width) + std::size_t(x)] = solution[i];
    }
    result.values.push_back(std::move(values));
  }
  return result;
}

}  // namespace geobrush
