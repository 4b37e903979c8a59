// The membrane with G = 0 over a planar triangulation (GeoBrush paper, Eq. 3): heights that are
// harmonic (L h = 0) or biharmonic (L M^-1 L h = 0) at the unknown points, with the cotangent
// Laplacian L and the barycentric areas M of the chart's triangles.
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "hole_membrane.hpp"

namespace geobrush {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

struct Operators {
  Eigen::SparseMatrix<double> laplacian;  // rows and columns over every point
  Eigen::VectorXd area;                   // barycentric area of each point
};

Operators cotangentOperators(const MembraneProblem& problem) {
  const int n = problem.pointCount;
  Triplets entries;
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  for (std::size_t t = 0; t < problem.triangles.size(); ++t) {
    const auto& tri = problem.triangles[t];
    const auto& p = problem.corners[t];
    const double twiceArea = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(twiceArea > 0.0)) continue;
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3];
      const Eigen::Vector3d u = p[k] - p[(k + 2) % 3], v = p[(k + 1) % 3] - p[(k + 2) % 3];
      const double weight = 0.5 * u.dot(v) / twiceArea;  // half the cotangent opposite i-j
      entries.emplace_back(i, j, weight);
      entries.emplace_back(j, i, weight);
      entries.emplace_back(i, i, -weight);
      entries.emplace_back(j, j, -weight);
    }
    // Mixed Voronoi areas (Meyer et al. 2003): a third of the area would favour skinny corners.
    double cot[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      cot[k] = u.dot(v) / twiceArea;
    }
    const int obtuse = cot[0] < 0 ? 0 : cot[1] < 0 ? 1 : cot[2] < 0 ? 2 : -1;
    for (int k = 0; k < 3; ++k) {
      if (obtuse >= 0) {
        area[tri[k]] += (k == obtuse ? 0.25 : 0.125) * twiceArea;
        continue;
      }
      const double next = (p[(k + 1) % 3] - p[k]).squaredNorm(),
                   prev = (p[(k + 2) % 3] - p[k]).squaredNorm();
      area[tri[k]] += (next * cot[(k + 2) % 3] + prev * cot[(k + 1) % 3]) / 8.0;
    }
  }
  Operators ops;
  ops.laplacian.resize(n, n);
  ops.laplacian.setFromTriplets(entries.begin(), entries.end());
  ops.area = area;
  return ops;
}

}  // namespace

Eigen::MatrixXd solveMembrane(const MembraneProblem& problem) {
  const int n = problem.pointCount, unknown = problem.unknownCount;
  if (unknown == 0) return Eigen::MatrixXd(0, problem.values.cols());
  if (problem.values.rows() != n || problem.corners.size() != problem.triangles.size() ||
      problem.completeCount < unknown || problem.completeCount > n)
    throw std::invalid_argument("solveMembrane: inconsistent problem sizes");
  const Operators ops = cotangentOperators(problem);
  // Rows over the unknowns, columns over every point; positive semi-definite on the unknowns.
  Eigen::SparseMatrix<double> system;
  if (problem.continuity == 0) {
    system = -ops.laplacian.topRows(unknown);
  } else {
    // Only the first completeCount points have whole rings, so only their Laplacians are known.
    const int complete = problem.completeCount;
    Eigen::VectorXd inverseArea(complete);
    for (int i = 0; i < complete; ++i) {
      if (!(ops.area[i] > 0.0)) throw std::runtime_error("a point of the chart has no area");
      inverseArea[i] = 1.0 / ops.area[i];
    }
    const Eigen::SparseMatrix<double> rows = ops.laplacian.topRows(complete);
    const Eigen::SparseMatrix<double> left = rows.leftCols(complete).topRows(unknown);
    system = left * inverseArea.asDiagonal() * rows;
  }
  const Eigen::SparseMatrix<double> inner = system.leftCols(unknown);
  const Eigen::MatrixXd rhs =
      -(system.rightCols(n - unknown) * problem.values.bottomRows(n - unknown));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(inner);
  if (solver.info() != Eigen::Success) throw std::runtime_error("the membrane system is singular");
  Eigen::MatrixXd solved = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !solved.allFinite())
    throw std::runtime_error("the membrane system has no solution");
  return solved;
}

}  // namespace geobrush
