#include "geobrush/geodesic_rbf.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "geobrush/parallel.hpp"

namespace geobrush {
namespace {

// exp(-s^2) is exactly 0 in doubles from s^2 = 746 on, so a Dijkstra bounded at this many t_max
// misses no nonzero phi.
const double kPhiVanishes = std::sqrt(746.0);

void requireValid(const KnnGraph& graph, std::span<const int> constraint,
                  std::span<const Eigen::Vector3d> displacement,
                  const GeodesicRbfOptions& options) {
  if (constraint.size() != displacement.size())
    throw std::invalid_argument("geodesic RBF: " + std::to_string(constraint.size()) +
                                " constraints but " + std::to_string(displacement.size()) +
                                " displacements");
  if (constraint.empty()) throw std::invalid_argument("geodesic RBF: no constraint");
  if (!options.straightPoints.empty() && options.straightPoints.size() != std::size_t(graph.size()))
    throw std::invalid_argument("geodesic RBF: the straight distances' points are not the graph's");
  if (!(options.tMax > 0) || !std::isfinite(options.tMax))
    throw std::invalid_argument("geodesic RBF: t_max must be a finite number > 0");
  if (!(options.reg >= 0) || !std::isfinite(options.reg))
    throw std::invalid_argument("geodesic RBF: reg must be a finite number >= 0");
  std::vector<char> used(std::size_t(graph.size()), 0);
  for (std::size_t i = 0; i < constraint.size(); ++i) {
    const int c = constraint[i];
    if (c < 0 || c >= graph.size())
      throw std::invalid_argument("geodesic RBF: constraint " + std::to_string(i) +
                                  " is no graph point");
    if (used[std::size_t(c)]++)
      throw std::invalid_argument("geodesic RBF: point " + std::to_string(c) +
                                  " is constrained twice");
    if (!displacement[i].allFinite())
      throw std::invalid_argument("geodesic RBF: displacement " + std::to_string(i) +
                                  " is not finite");
  }
}

// The basis is made this many constraints at a time: its N x K values would not fit in memory
// for large templates, so each pass below recomputes the columns it reads.
constexpr std::size_t kColumnsAtATime = 16;

std::vector<double> straightDistances(std::span<const Eigen::Vector3d> points, int from) {
  std::vector<double> distance(points.size());
  for (std::size_t x = 0; x < points.size(); ++x)
    distance[x] = (points[x] - points[std::size_t(from)]).norm();
  return distance;
}

// Columns first..last-1 of Eq. 4's basis: phi(delta(c_i, x)) at every graph point x, one
// Dijkstra each.
Eigen::MatrixXd basisColumns(const KnnGraph& graph, std::span<const int> constraint,
                             const GeodesicRbfOptions& options, std::size_t first,
                             std::size_t last) {
  const double tMax = options.tMax;
  const bool scodef = options.kernel == RbfKernel::Scodef;
  const double reach = scodef ? tMax : kPhiVanishes * tMax;
  Eigen::MatrixXd phi(graph.size(), Eigen::Index(last - first));
  parallelBlocks(last - first, 1, 0, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const int source[] = {constraint[first + i]};
      const auto distance = options.straightPoints.empty()
                                ? graphDistances(graph, source, reach)
                                : straightDistances(options.straightPoints, source[0]);
      for (int x = 0; x < graph.size(); ++x) {
        const double d = distance[std::size_t(x)];
        phi(x, Eigen::Index(i)) = d == kUnreached ? 0.0
                                  : scodef        ? scodefRbf(d, tMax)
                                                  : gaussianRbf(d, tMax);
      }
    }
  });
  return phi;
}

// Calls use(i, column i of the basis) for each constraint in order.
template <typename Use>
void forEachBasisColumn(const KnnGraph& graph, std::span<const int> constraint,
                        const GeodesicRbfOptions& options, const Use& use) {
  for (std::size_t first = 0; first < constraint.size(); first += kColumnsAtATime) {
    const std::size_t last = std::min(constraint.size(), first + kColumnsAtATime);
    const Eigen::MatrixXd phi = basisColumns(graph, constraint, options, first, last);
    for (std::size_t i = first; i < last; ++i)
      use(i, phi.col(Eigen::Index(i - first)));
  }
}

// A_ij = phi(delta(c_i, c_j)) (Eq. 6). Dijkstra's sums along a path and its reverse may differ in
// the last bit, so A is symmetrised for the symmetric solver.
Eigen::MatrixXd systemMatrix(const KnnGraph& graph, std::span<const int> constraint,
                             const GeodesicRbfOptions& options) {
  const Eigen::Index k = Eigen::Index(constraint.size());
  Eigen::MatrixXd a(k, k);
  forEachBasisColumn(graph, constraint, options, [&](std::size_t i, const auto& column) {
    for (Eigen::Index j = 0; j < k; ++j)
      a(j, Eigen::Index(i)) = column(constraint[std::size_t(j)]);
  });
  return 0.5 * (a + a.transpose());
}

// A's eigenvalues moved away from 0 by reg, keeping their signs (GeodesicRbfOptions::reg).
Eigen::VectorXd shifted(const Eigen::VectorXd& lambda, double reg) {
  return lambda.unaryExpr([reg](double l) { return l < 0 ? l - reg : l + reg; });
}

}  // namespace

GeodesicRbfResult geodesicRbf(const KnnGraph& graph, std::span<const int> constraint,
                              std::span<const Eigen::Vector3d> displacement,
                              const GeodesicRbfOptions& options) {
  requireValid(graph, constraint, displacement, options);
  GeodesicRbfResult result;
  result.system = systemMatrix(graph, constraint, options);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(result.system);
  if (eigen.info() != Eigen::Success)
    throw std::invalid_argument("geodesic RBF: the eigen-decomposition of A did not converge");
  result.smallestEigenvalue = eigen.eigenvalues().minCoeff();
  result.largestEigenvalue = eigen.eigenvalues().maxCoeff();
  const Eigen::VectorXd lambda = shifted(eigen.eigenvalues(), options.reg);
  const double smallest = lambda.cwiseAbs().minCoeff();
  if (!(smallest > 0))
    throw std::invalid_argument(
        "geodesic RBF: A is singular (constraints at graph distance 0?): raise reg");
  result.conditionNumber = lambda.cwiseAbs().maxCoeff() / smallest;

  Eigen::MatrixX3d d(Eigen::Index(constraint.size()), 3);
  for (std::size_t i = 0; i < constraint.size(); ++i)
    d.row(Eigen::Index(i)) = displacement[i].transpose();
  const Eigen::MatrixXd& v = eigen.eigenvectors();
  result.weights = v * (lambda.cwiseInverse().asDiagonal() * (v.transpose() * d));

  result.displacement.assign(std::size_t(graph.size()), Eigen::Vector3d::Zero());
  // Summed in constraint order at every point (Eq. 4).
  forEachBasisColumn(graph, constraint, options, [&](std::size_t i, const auto& column) {
    const Eigen::Vector3d weight = result.weights.row(Eigen::Index(i)).transpose();
    for (int x = 0; x < graph.size(); ++x)
      result.displacement[std::size_t(x)] += column(x) * weight;
  });
  return result;
}

}  // namespace geobrush
