#include "geobrush/sparse_cholesky.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "canvas_fixtures.hpp"
#include "geobrush/laplacian.hpp"

namespace geobrush {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// The cotangent Laplacian of a flat grid with its border held (Dirichlet rows), symmetric positive
// definite: the system of a harmonic fill.
struct HeldGrid {
  Sparse laplacian;  // before the border was held
  Sparse system;
  std::vector<bool> border;
};

HeldGrid heldGrid(int n) {
  const MeshPtr grid = test::heightGrid(n, [](double, double) { return 0.0; });
  const TriMesh& mesh = grid->surface;
  const Sparse laplacian = cotangentLaplacian(mesh);
  Sparse system = laplacian;
  std::vector<bool> border(mesh.n_vertices());
  for (auto v : mesh.vertices())
    border[std::size_t(v.idx())] = mesh.is_boundary(v);
  for (int j = 0; j < system.outerSize(); ++j)
    for (Sparse::InnerIterator it(system, j); it; ++it)
      if (border[std::size_t(it.row())] || border[std::size_t(it.col())])
        it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
  return {laplacian, system, border};
}

// A linear function of the plane is harmonic: held at the border it is the solution inside.
TEST(SparseCholesky, SolvesAHarmonicFillOfAPlaneExactly) {
  const MeshPtr grid = test::heightGrid(16, [](double, double) { return 0.0; });
  const TriMesh& mesh = grid->surface;
  const HeldGrid held = heldGrid(16);
  Eigen::VectorXd linear(mesh.n_vertices()), heldValues = Eigen::VectorXd::Zero(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    linear[v.idx()] = 0.3 + 2 * p[0] - 0.5 * p[1];
    if (held.border[std::size_t(v.idx())]) heldValues[v.idx()] = linear[v.idx()];
  }
  // Inside, L x = 0 with the border's share moved to the right-hand side.
  Eigen::VectorXd rhs = -(held.laplacian * heldValues);
  for (auto v : mesh.vertices())
    if (held.border[std::size_t(v.idx())]) rhs[v.idx()] = linear[v.idx()];
  const SparseCholesky cholesky(held.system);
  ASSERT_EQ(cholesky.info(), Eigen::Success);
  EXPECT_EQ(cholesky.rows(), held.system.rows());
  EXPECT_LT((cholesky.solve(rhs).col(0) - linear).cwiseAbs().maxCoeff(), 1e-12);
}

// One symbolic analysis serves every numeric factorization of the same pattern, and a matrix
// right-hand side gives its columns' solutions.
TEST(SparseCholesky, RefactorsOnePatternAndSolvesColumnsAlike) {
  const HeldGrid held = heldGrid(12);
  SparseCholesky cholesky;
  cholesky.analyzePattern(held.system);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(held.system.rows(), 3);
  for (double shift : {0.0, 1.0, 10.0}) {
    Sparse shifted = held.system;
    for (int i = 0; i < shifted.rows(); ++i)
      shifted.coeffRef(i, i) += shift;
    cholesky.factorize(shifted);
    ASSERT_EQ(cholesky.info(), Eigen::Success);
    const Eigen::MatrixXd x = cholesky.solve(rhs);
    EXPECT_LT((shifted * x - rhs).cwiseAbs().maxCoeff(), 1e-10) << shift;
    EXPECT_LT((cholesky.solve(rhs.col(1)) - x.col(1)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(SparseCholesky, RefusesAnIndefiniteMatrix) {
  Sparse indefinite(2, 2);
  indefinite.insert(0, 0) = 1;
  indefinite.insert(1, 1) = -1;
  EXPECT_EQ(SparseCholesky(indefinite).info(), Eigen::NumericalIssue);
}

// Nodes share factors across threads: concurrent solves give the one-thread answer, bit for bit.
TEST(SparseCholesky, SolvesFromSeveralThreadsAtOnce) {
  const HeldGrid held = heldGrid(24);
  const SparseCholesky cholesky(held.system);
  ASSERT_EQ(cholesky.info(), Eigen::Success);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(held.system.rows(), -1, 1);
  const Eigen::MatrixXd expected = cholesky.solve(rhs);
  std::vector<Eigen::MatrixXd> results(4);
  std::vector<std::thread> threads;
  for (auto& result : results)
    threads.emplace_back([&] {
      for (int k = 0; k < 20; ++k)
        result = cholesky.solve(rhs);
    });
  for (auto& thread : threads)
    thread.join();
  for (const auto& result : results)
    EXPECT_EQ(result, expected);
}

}  // namespace
}  // namespace geobrush
