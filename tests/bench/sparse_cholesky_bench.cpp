// The sparse Cholesky factorization the nodes share (CHOLMOD's supernodal LL^T) against Eigen's
// simplicial LDL^T, on the systems the EMD nodes factor, in one process.
#include <benchmark/benchmark.h>

#include <Eigen/SparseCholesky>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "geobrush/laplacian.hpp"
#include "geobrush/sparse_cholesky.hpp"

namespace geobrush {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Argument 0: the relief plane's quads per side ((r + 1)^2 vertices); argument 1: the operator
// (0: L + M, the screened reconstruction's 1-ring system; 1: L M^-1 L + M, the biharmonic
// envelope's 2-ring one).
Sparse system(const benchmark::State& state) {
  const MeshPtr plane = test::heightGrid(int(state.range(0)), [](double x, double y) {
    return 0.02 * std::sin(40 * x) * std::cos(37 * y);
  });
  const TriMesh& mesh = plane->surface;
  const Sparse laplacian = cotangentLaplacian(mesh);
  const Eigen::VectorXd areas = vertexAreas(mesh);
  Sparse mass(laplacian.rows(), laplacian.cols());
  mass.setIdentity();
  mass = areas.asDiagonal() * mass;
  if (state.range(1) == 0) return Sparse(laplacian + mass);
  return Sparse(Sparse(laplacian * areas.cwiseInverse().asDiagonal() * laplacian) + mass);
}

// Argument 2: 0 Eigen's SimplicialLDLT, 1 SparseCholesky. The pattern analyzed once; one numeric
// factorization and one solve per iteration, as each sift and each dab does.
void BM_Factorize(benchmark::State& state) {
  const Sparse matrix = system(state);
  const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(matrix.rows());
  double residual = 0;
  if (state.range(2) == 0) {
    Eigen::SimplicialLDLT<Sparse> ldlt;
    ldlt.analyzePattern(matrix);
    for (auto _ : state) {
      ldlt.factorize(matrix);
      residual = (matrix * ldlt.solve(rhs) - rhs).norm();
    }
  } else {
    SparseCholesky llt;
    llt.analyzePattern(matrix);
    for (auto _ : state) {
      llt.factorize(matrix);
      residual = (matrix * llt.solve(rhs).col(0) - rhs).norm();
    }
  }
  state.counters["vertices"] = double(matrix.rows());
  state.counters["residual"] = residual;
}

}  // namespace
}  // namespace geobrush

BENCHMARK(geobrush::BM_Factorize)
    ->ArgsProduct({{140, 316}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
