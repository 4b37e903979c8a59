#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <Eigen/Geometry>

#include "geobrush/loop_zip.hpp"

namespace geobrush {
namespace {

// n points on a circle of radius r, counterclockwise, the first at angle `phase`.
std::vector<Eigen::Vector2d> circle(int n, double r, double phase = 0) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < n; ++i) {
    const double t = phase + 2 * std::numbers::pi * i / n;
    points.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  return points;
}

std::vector<int> ids(int first, int n) {
  std::vector<int> out;
  for (int i = 0; i < n; ++i)
    out.push_back(first + i);
  return out;
}

// Each undirected edge of the triangles, counted.
std::map<std::pair<int, int>, int> edgeUses(const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      uses[std::minmax(t[k], t[(k + 1) % 3])]++;
  return uses;
}

// Both loops run in the direction of their boundary halfedges: a patch's clockwise (against its
// counterclockwise faces), the hole's around it counterclockwise.
TEST(LoopZip, ConcentricLoopsGiveNPlusMTrianglesEachCounterclockwise) {
  for (auto [n, m] : {std::pair{12, 12}, {7, 19}, {30, 5}}) {
    auto inner = circle(n, 1.0, 0.1);
    std::reverse(inner.begin(), inner.end());
    const auto outer = circle(m, 2.0);
    const DomainZipMetric metric(inner, outer);
    const auto triangles = zipLoops(ids(0, n), ids(n, m), metric, false);
    ASSERT_EQ(triangles.size(), std::size_t(n + m));
    std::vector<Eigen::Vector2d> all = inner;
    all.insert(all.end(), outer.begin(), outer.end());
    for (const auto& t : triangles) {
      const Eigen::Vector2d e = all[t[1]] - all[t[0]], f = all[t[2]] - all[t[0]];
      EXPECT_GT(e.x() * f.y() - e.y() * f.x(), 0);
    }
    // A closed strip: every loop edge once, every new edge twice.
    for (const auto& [edge, count] : edgeUses(triangles)) {
      const bool innerEdge = edge.second < n, outerEdge = edge.first >= n;
      EXPECT_EQ(count, innerEdge || outerEdge ? 1 : 2) << edge.first << "-" << edge.second;
    }
  }
}

TEST(LoopZip, InSpaceTheStripFacesTheSurfaceNormals) {
  const int n = 16, m = 24;
  std::vector<Eigen::Vector3d> inner, outer, up(std::max(n, m), Eigen::Vector3d::UnitZ());
  auto patch = circle(n, 1.0, 0.05);
  std::reverse(patch.begin(), patch.end());
  for (const auto& p : patch)
    inner.emplace_back(p.x(), p.y(), 0.3);
  for (const auto& p : circle(m, 1.5))
    outer.emplace_back(p.x(), p.y(), 0.0);
  const SpaceZipMetric metric(inner, outer, up, up);
  const auto triangles = zipLoops(ids(0, n), ids(n, m), metric, false);
  ASSERT_EQ(triangles.size(), std::size_t(n + m));
  std::vector<Eigen::Vector3d> all = inner;
  all.insert(all.end(), outer.begin(), outer.end());
  for (const auto& t : triangles) {
    const Eigen::Vector3d normal = (all[t[1]] - all[t[0]]).cross(all[t[2]] - all[t[0]]);
    EXPECT_GT(normal.z(), 0);
  }
}

}  // namespace
}  // namespace geobrush
