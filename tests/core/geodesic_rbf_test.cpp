#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "geobrush/geodesic_rbf.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

// The n x n unit-spaced grid in the plane z = 0, row by row.
std::vector<Vector3d> grid(int n) {
  std::vector<Vector3d> points;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      points.emplace_back(x, y, 0);
  return points;
}

// The grid points on the square ring at Chebyshev distance `r` from the centre of an n x n grid,
// every `step`-th cell along x and y.
std::vector<int> ring(int n, int r, int step = 1) {
  const int c = n / 2;
  std::vector<int> points;
  for (int y = c - r; y <= c + r; y += step)
    for (int x = c - r; x <= c + r; x += step)
      if (std::max(std::abs(x - c), std::abs(y - c)) == r) points.push_back(y * n + x);
  return points;
}

// A smooth, non-constant displacement per constraint.
std::vector<Vector3d> wavy(const std::vector<Vector3d>& points, const std::vector<int>& at) {
  std::vector<Vector3d> d;
  for (int v : at) {
    const Vector3d& p = points[std::size_t(v)];
    d.emplace_back(0.1 * std::sin(0.3 * p.y()), 0.05 * p.x(), 1.0 + 0.2 * std::cos(0.4 * p.x()));
  }
  return d;
}

double maxMiss(const GeodesicRbfResult& result, const std::vector<int>& at,
               const std::vector<Vector3d>& wanted) {
  double worst = 0;
  for (std::size_t i = 0; i < at.size(); ++i)
    worst = std::max(worst, (result.displacement[std::size_t(at[i])] - wanted[i]).norm());
  return worst;
}

// Eq. 6 makes Eq. 4 interpolate: d_h(t_b_i) = d_i.
TEST(GeodesicRbf, InterpolatesEveryConstraint) {
  const int n = 31;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 8, 2);
  const auto d = wavy(points, at);
  GeodesicRbfOptions options;
  options.tMax = 10;
  const auto result = geodesicRbf(graph, at, d, options);
  RecordProperty("condition_number", std::to_string(result.conditionNumber));
  EXPECT_GT(result.conditionNumber, 1);
  EXPECT_LT(maxMiss(result, at, d), 1e-9);
  ASSERT_EQ(result.displacement.size(), points.size());
}

// Without a polynomial term a constant is not reproduced: every constraint holds it and every
// displacement is parallel to it (each D_i is a multiple of it), but its size varies between
// and beyond the constraints, as sum_i phi_i(x) (A^-1 1)_i is not 1.
TEST(GeodesicRbf, ConstantDisplacementHoldsAtConstraintsOnlyAndStaysParallel) {
  const int n = 31;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 6, 3);
  const Vector3d c(0.3, -0.2, 0.5);
  const std::vector<Vector3d> d(at.size(), c);
  GeodesicRbfOptions options;
  options.tMax = 8;
  const auto result = geodesicRbf(graph, at, d, options);
  EXPECT_LT(maxMiss(result, at, d), 1e-10);
  double smallest = 1e300, largest = 0;
  for (const auto& x : result.displacement) {
    EXPECT_LT(x.cross(c).norm(), 1e-12 * c.norm() * (1 + x.norm()));
    smallest = std::min(smallest, x.norm());
    largest = std::max(largest, x.norm());
  }
  EXPECT_LT(smallest, 0.9 * c.norm());  // falls off toward the grid's corners
  RecordProperty("size_range",
                 std::to_string(smallest / c.norm()) + " .. " + std::to_string(largest / c.norm()));
}

// The paper's t_max (the bounding diagonal) makes phi in [1/e, 1] everywhere, so dense
// constraints give a near-singular A, and on graph distances an indefinite one. reg moves each
// eigenvalue away from 0 by reg: the condition number drops to (max|l| + reg) / (min|l| + reg),
// and the constraints then hold up to reg sign(A) D.
TEST(GeodesicRbf, RegularisationLowersTheConditionNumber) {
  const int n = 21;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 7);
  const auto d = wavy(points, at);
  GeodesicRbfOptions options;
  options.tMax = std::sqrt(2.0) * (n - 1);
  const auto exact = geodesicRbf(graph, at, d, options);
  const double reg = 1e-2;
  options.reg = reg;
  const auto regular = geodesicRbf(graph, at, d, options);
  RecordProperty("condition_number", std::to_string(exact.conditionNumber));
  RecordProperty("condition_number_reg", std::to_string(regular.conditionNumber));
  EXPECT_LT(exact.smallestEigenvalue, 0);  // the graph metric is not Euclidean
  EXPECT_GT(exact.conditionNumber, 1e5);
  EXPECT_LT(regular.conditionNumber, 1e-2 * exact.conditionNumber);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(exact.system);
  const Eigen::VectorXd size = eigen.eigenvalues().cwiseAbs();
  EXPECT_NEAR(regular.conditionNumber, (size.maxCoeff() + reg) / (size.minCoeff() + reg),
              1e-9 * regular.conditionNumber);
  // Eq. 4 at the constraints is A D: it meets d - reg sign(A) D.
  const Eigen::MatrixXd sign = eigen.eigenvectors() * eigen.eigenvalues().cwiseSign().asDiagonal() *
                               eigen.eigenvectors().transpose();
  const Eigen::MatrixX3d held = -reg * sign * regular.weights;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const Vector3d want = d[i] + held.row(Eigen::Index(i)).transpose();
    EXPECT_LT((regular.displacement[std::size_t(at[i])] - want).norm(), 1e-10) << i;
  }
  EXPECT_GT(maxMiss(regular, at, d), 1e-6);
  EXPECT_LT(maxMiss(exact, at, d), 1e-9);
}

// Where A is positive definite (narrow t_max, sparse constraints) the shift is plain Tikhonov.
TEST(GeodesicRbf, RegularisationIsTikhonovWhereAIsPositiveDefinite) {
  const int n = 21;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 7, 2);
  const auto d = wavy(points, at);
  GeodesicRbfOptions options;
  options.tMax = 2;
  options.reg = 0.1;
  const auto regular = geodesicRbf(graph, at, d, options);
  ASSERT_GT(regular.smallestEigenvalue, 0);
  Eigen::MatrixXd tikhonov = regular.system;
  tikhonov.diagonal().array() += 0.1;
  Eigen::MatrixX3d rhs(Eigen::Index(at.size()), 3);
  for (std::size_t i = 0; i < at.size(); ++i)
    rhs.row(Eigen::Index(i)) = d[i].transpose();
  const Eigen::MatrixX3d expected = tikhonov.ldlt().solve(rhs);
  EXPECT_LT((regular.weights - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(GeodesicRbf, PointsNoConstraintReachesStayPut) {
  std::vector<Vector3d> points = grid(5);
  for (const auto& p : grid(5))
    points.push_back(p + Vector3d(100, 0, 0));
  const KnnGraph graph(points, 4);
  const std::vector<int> at{0, 6, 12};
  const std::vector<Vector3d> d(3, Vector3d(0, 0, 1));
  const auto result = geodesicRbf(graph, at, d);
  for (std::size_t v = 25; v < points.size(); ++v)
    EXPECT_EQ(result.displacement[v], Vector3d::Zero()) << v;
  EXPECT_GT(result.displacement[24].z(), 0);
}

TEST(GeodesicRbf, RepeatsBitForBit) {
  const int n = 25;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 9);
  const auto d = wavy(points, at);
  const auto a = geodesicRbf(graph, at, d);
  const auto b = geodesicRbf(graph, at, d);
  ASSERT_EQ(a.displacement.size(), b.displacement.size());
  for (std::size_t v = 0; v < a.displacement.size(); ++v)
    ASSERT_EQ(a.displacement[v], b.displacement[v]) << v;
}

TEST(GeodesicRbf, RefusesBadInput) {
  const auto points = grid(5);
  const KnnGraph graph(points, 4);
  const std::vector<Vector3d> d(2, Vector3d(0, 0, 1));
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 2, 3}, d), std::invalid_argument);
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{}, std::vector<Vector3d>{}),
               std::invalid_argument);
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 1}, d), std::invalid_argument);
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 25}, d), std::invalid_argument);
  const std::vector<Vector3d> notFinite{Vector3d(0, 0, 1), Vector3d(0, NAN, 0)};
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 2}, notFinite), std::invalid_argument);
  GeodesicRbfOptions options;
  options.tMax = 0;
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 2}, d, options), std::invalid_argument);
  options.tMax = 1;
  options.reg = -1;
  EXPECT_THROW(geodesicRbf(graph, std::vector<int>{1, 2}, d, options), std::invalid_argument);
}

// Straight distances: the plain Gaussian RBF interpolant, checked against a dense solve done
// here, and positive definite (every eigenvalue of A above 0), unlike the graph's.
TEST(GeodesicRbf, StraightDistancesGiveThePlainGaussianInterpolant) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      points.emplace_back(0.1 * i, 0.1 * j, 0.02 * std::sin(double(i * j)));
  const KnnGraph graph(points, 8);
  const std::vector<int> constraint = {0, 11, 60, 77, 132, 143};
  std::vector<Eigen::Vector3d> displacement;
  for (std::size_t i = 0; i < constraint.size(); ++i)
    displacement.emplace_back(0.1 * double(i), -0.05, 0.2 * std::cos(double(i)));
  GeodesicRbfOptions options;
  options.tMax = 0.4;
  options.straightPoints = points;
  const GeodesicRbfResult result = geodesicRbf(graph, constraint, displacement, options);
  EXPECT_GT(result.smallestEigenvalue, 0);
  const auto k = Eigen::Index(constraint.size());
  Eigen::MatrixXd a(k, k);
  Eigen::MatrixX3d d(k, 3);
  for (Eigen::Index i = 0; i < k; ++i) {
    d.row(i) = displacement[std::size_t(i)].transpose();
    for (Eigen::Index j = 0; j < k; ++j)
      a(i, j) = gaussianRbf((points[std::size_t(constraint[std::size_t(i)])] -
                             points[std::size_t(constraint[std::size_t(j)])])
                                .norm(),
                            options.tMax);
  }
  const Eigen::MatrixX3d weights = a.ldlt().solve(d);
  for (std::size_t x = 0; x < points.size(); ++x) {
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i < k; ++i)
      expected += gaussianRbf((points[std::size_t(constraint[std::size_t(i)])] - points[x]).norm(),
                              options.tMax) *
                  weights.row(i).transpose();
    ASSERT_LT((result.displacement[x] - expected).norm(), 1e-9) << x;
  }
  options.straightPoints = std::span<const Eigen::Vector3d>(points).first(5);
  EXPECT_THROW(geodesicRbf(graph, constraint, displacement, options), std::invalid_argument);
}

// SCODEF's kernel (Borrel and Rappoport 1994): the cubic 1 - 3s^2 + 2s^3 with compact support.
// The constraints hold, and a point farther than t_max from every constraint does not move.
TEST(GeodesicRbf, TheScodefKernelInterpolatesWithCompactSupport) {
  EXPECT_EQ(scodefRbf(0, 2), 1.0);
  EXPECT_EQ(scodefRbf(1, 2), 0.5);
  EXPECT_EQ(scodefRbf(2, 2), 0.0);
  EXPECT_EQ(scodefRbf(3, 2), 0.0);
  const int n = 31;
  const auto points = grid(n);
  const KnnGraph graph(points, 8);
  const auto at = ring(n, 4, 2);
  const auto d = wavy(points, at);
  GeodesicRbfOptions options;
  options.kernel = RbfKernel::Scodef;
  options.tMax = 5;
  options.straightPoints = points;
  const auto result = geodesicRbf(graph, at, d, options);
  EXPECT_LT(maxMiss(result, at, d), 1e-9);
  for (std::size_t x = 0; x < points.size(); ++x) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int c : at)
      nearest = std::min(nearest, (points[x] - points[std::size_t(c)]).norm());
    if (nearest >= options.tMax) {
      EXPECT_EQ(result.displacement[x], Vector3d::Zero()) << x;
    }
  }
  // The grid's corner is far from the ring: untouched; the centre, inside it, moves.
  EXPECT_EQ(result.displacement[0], Vector3d::Zero());
  EXPECT_GT(result.displacement[std::size_t((n / 2) * n + n / 2)].norm(), 0.5);
}

}  // namespace
}  // namespace geobrush
