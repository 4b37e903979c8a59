#include "geobrush/point_neighbours.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The k nearest by brute force: distance, then index.
std::vector<int> bruteNearest(const std::vector<Eigen::Vector3d>& points,
                              const Eigen::Vector3d& query, int k) {
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return (points[std::size_t(a)] - query).squaredNorm() <
           (points[std::size_t(b)] - query).squaredNorm();
  });
  order.resize(std::min(std::size_t(k), order.size()));
  return order;
}

std::vector<Eigen::Vector3d> cubeGrid(int n) {
  std::vector<Eigen::Vector3d> points;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        points.emplace_back(x, y, z);
  return points;
}

TEST(PointNeighbours, MatchesBruteForceOnAMesh) {
  const auto mesh = readMesh(test::meshPath("bunny_small.obj")).mesh;
  std::vector<Eigen::Vector3d> points;
  for (const auto v : mesh->surface.vertices())
    points.push_back(pointOf(mesh->surface, v));
  const PointNeighbours tree(points);
  ASSERT_EQ(tree.size(), points.size());
  for (std::size_t i = 0; i < points.size(); i += 7) {
    const Eigen::Vector3d query = points[i] + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
    EXPECT_EQ(tree.nearest(query, 7), bruteNearest(points, query, 7)) << "query " << i;
  }
}

// At the centre of a unit cube of grid points all 8 corners tie, and at a grid point its 6 axis
// neighbours do: whichever k cuts through a tie, the lower indices come first.
TEST(PointNeighbours, TiesGoToTheLowerIndexEvenAcrossTheKthPlace) {
  const auto points = cubeGrid(4);
  const PointNeighbours tree(points);
  for (int k = 1; k <= 12; ++k) {
    EXPECT_EQ(tree.nearest({1.5, 1.5, 1.5}, k), bruteNearest(points, {1.5, 1.5, 1.5}, k)) << k;
    EXPECT_EQ(tree.nearest({1, 2, 1}, k), bruteNearest(points, {1, 2, 1}, k)) << k;
  }
  EXPECT_EQ(tree.nearest({1.5, 1.5, 1.5}, 3), (std::vector<int>{21, 22, 25}));
}

TEST(PointNeighbours, ReturnsAtMostTheSetAndNothingForKBelowOne) {
  const PointNeighbours tree(cubeGrid(2));
  EXPECT_EQ(tree.nearest({0, 0, 0}, 20).size(), 8u);
  EXPECT_TRUE(tree.nearest({0, 0, 0}, 0).empty());
  EXPECT_TRUE(tree.nearest({0, 0, 0}, -3).empty());
  const PointNeighbours empty({});
  EXPECT_TRUE(empty.nearest({0, 0, 0}, 3).empty());
}

TEST(PointNeighbours, RefusesNonFinitePointsAndQueries) {
  std::vector<Eigen::Vector3d> points = cubeGrid(2);
  points[5].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    const PointNeighbours tree(points);
    ADD_FAILURE() << "accepted a NaN point";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point 5"), std::string::npos) << e.what();
  }
  const PointNeighbours tree(cubeGrid(2));
  EXPECT_THROW(tree.nearest({std::numeric_limits<double>::infinity(), 0, 0}, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace geobrush
