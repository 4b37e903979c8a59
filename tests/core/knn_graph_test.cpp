#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geobrush/knn_graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

std::vector<Eigen::Vector3d> squareGrid(int n) {
  std::vector<Eigen::Vector3d> points;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      points.emplace_back(x, y, 0);
  return points;
}

bool isSymmetric(const KnnGraph& graph) {
  for (int v = 0; v < graph.size(); ++v)
    for (const KnnEdge& e : graph.neighbours(v)) {
      bool back = false;
      for (const KnnEdge& f : graph.neighbours(e.to))
        back = back || (f.to == v && f.length == e.length);
      if (!back) return false;
    }
  return true;
}

// U2: with k = 8 on a square grid the paths take axis and diagonal steps, so the graph distance
// lies between the Euclidean one and the octile bound sqrt(4 - 2 sqrt2) ~ 1.0824 times it.
TEST(KnnGraph, GridDistancesLieBetweenEuclideanAndTheOctileBound) {
  const int n = 21;
  const auto points = squareGrid(n);
  const KnnGraph graph(points, 8);
  EXPECT_TRUE(isSymmetric(graph));
  const int centre = (n / 2) * n + n / 2;
  const auto distance = graphDistances(graph, std::vector<int>{centre});
  const double bound = std::sqrt(4 - 2 * std::numbers::sqrt2);
  double worst = 1;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double euclidean = (points[p] - points[std::size_t(centre)]).norm();
    ASSERT_GE(distance[p], euclidean - 1e-12) << p;
    ASSERT_LE(distance[p], bound * euclidean + 1e-12) << p;
    if (euclidean > 0) worst = std::max(worst, distance[p] / euclidean);
  }
  EXPECT_GE(worst, (1 + std::numbers::sqrt2) / std::sqrt(5.0) - 1e-12);  // the (2, 1) offset
  // Along an axis and a diagonal the path is straight.
  EXPECT_DOUBLE_EQ(distance[std::size_t(centre + 5)], 5.0);
  EXPECT_DOUBLE_EQ(distance[std::size_t(centre + 5 * n + 5)], 5 * std::numbers::sqrt2);
}

// U2: on a densely sampled cylinder the distance to the antipodal point of a ring is close to
// half the circumference, pi r, and never below the chord 2r.
TEST(KnnGraph, CylinderAntipodeIsHalfTheCircumferenceAway) {
  const double r = 1;
  const int around = 200, along = 20;
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const double t = 2 * std::numbers::pi * i / around;
      points.emplace_back(r * std::cos(t), r * std::sin(t), 0.02 * j);
    }
  const KnnGraph graph(points, 8);
  EXPECT_TRUE(isSymmetric(graph));
  const auto distance = graphDistances(graph, std::vector<int>{0});
  const double antipode = distance[std::size_t(around / 2)];
  EXPECT_NEAR(antipode, std::numbers::pi * r, 1e-3 * std::numbers::pi * r);
  EXPECT_GT(antipode, 2 * r);
}

TEST(KnnGraph, BoundedSearchAgreesInsideItsBallAndLeavesTheRestUnreached) {
  const auto points = squareGrid(30);
  const KnnGraph graph(points, 8);
  const std::vector<int> sources = {0, 899};
  const auto all = graphDistances(graph, sources);
  const auto near = graphDistances(graph, sources, 6.0);
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (all[p] <= 6.0) {
      EXPECT_EQ(near[p], all[p]) << p;
    } else {
      EXPECT_EQ(near[p], kUnreached) << p;
    }
  }
  EXPECT_EQ(all[0], 0);
  EXPECT_EQ(all[899], 0);
}

TEST(KnnGraph, CoincidentPointsAndSeparateClusters) {
  std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {100, 0, 0}, {101, 0, 0}};
  const KnnGraph graph(points, 1);
  EXPECT_TRUE(isSymmetric(graph));
  const auto distance = graphDistances(graph, std::vector<int>{0});
  EXPECT_EQ(distance[1], 0);
  EXPECT_EQ(distance[3], kUnreached);  // the far pair is its own component
  EXPECT_THROW(KnnGraph(points, 0), std::invalid_argument);
  points[2].x() = std::nan("");
  EXPECT_THROW(KnnGraph(points, 8), std::invalid_argument);
  const KnnGraph ok(std::vector<Eigen::Vector3d>{{0, 0, 0}}, 8);
  EXPECT_EQ(ok.edgeCount(), 0u);
  EXPECT_THROW(graphDistances(ok, std::vector<int>{1}), std::out_of_range);
}

// On a real scan: symmetric, connected, and every graph distance at least the straight one.
TEST(KnnGraph, BunnyScanDistancesBoundTheStraightLine) {
  const auto mesh = readMesh(test::meshPath("bunny_small.obj")).mesh;
  std::vector<Eigen::Vector3d> points;
  for (const auto v : mesh->surface.vertices())
    points.push_back(pointOf(mesh->surface, v));
  const KnnGraph graph(points, 8);
  EXPECT_TRUE(isSymmetric(graph));
  EXPECT_GE(graph.edgeCount(), 4 * points.size());
  const auto distance = graphDistances(graph, std::vector<int>{0});
  for (std::size_t p = 0; p < points.size(); ++p) {
    ASSERT_NE(distance[p], kUnreached) << p;
    ASSERT_GE(distance[p], (points[p] - points[0]).norm() - 1e-12) << p;
  }
}

}  // namespace
}  // namespace geobrush
