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

// The polygon a, b (chains with common ends) filled: each of its sides used once in its
// direction, each new edge twice in opposite directions, and no other edge.
void expectFillsPolygon(const std::vector<int>& a, const std::vector<int>& b,
                        const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : triangles) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
    for (int k = 0; k < 3; ++k)
      directed[{t[k], t[(k + 1) % 3]}]++;
  }
  for (const auto* chain : {&a, &b})
    for (std::size_t i = 0; i + 1 < chain->size(); ++i) {
      const std::pair side{(*chain)[i], (*chain)[i + 1]};
      EXPECT_EQ(directed[side], 1) << side.first << "->" << side.second;
      directed.erase(side);
    }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << edge.first << "->" << edge.second;
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
  }
}

double signedArea(const std::vector<Eigen::Vector2d>& points, const std::array<int, 3>& t) {
  const Eigen::Vector2d e = points[t[1]] - points[t[0]], f = points[t[2]] - points[t[0]];
  return e.x() * f.y() - e.y() * f.x();
}

// Chain b along the x axis from (0, 0) to (q, 0), chain a back over an arch above it: a
// counterclockwise polygon.
TEST(ZipChains, AnArchOverALineGivesPPlusQMinusTwoCounterclockwiseTriangles) {
  for (auto [p, q] : {std::pair{2, 2}, {5, 3}, {3, 8}, {6, 1}}) {
    std::vector<Eigen::Vector2d> points;  // b's vertices first, then a's inner ones
    for (int j = 0; j <= q; ++j)
      points.emplace_back(j, 0);
    std::vector<int> b = ids(0, q + 1), a{q};
    for (int i = 1; i < p; ++i) {
      const double t = std::numbers::pi * i / p;
      points.emplace_back(0.5 * q * (1 + std::cos(t)), 0.5 * q * std::sin(t));
      a.push_back(int(points.size()) - 1);
    }
    a.push_back(0);
    std::vector<Eigen::Vector2d> onA, onB;
    for (int v : a)
      onA.push_back(points[std::size_t(v)]);
    for (int v : b)
      onB.push_back(points[std::size_t(v)]);
    const auto triangles = zipChains(a, b, DomainZipMetric(onA, onB), true);
    ASSERT_EQ(triangles.size(), std::size_t(p + q - 2)) << p << " " << q;
    for (const auto& t : triangles)
      EXPECT_GT(signedArea(points, t), 1e-9) << p << " " << q;  // none flat, none turned over
    expectFillsPolygon(a, b, triangles);
  }
}

TEST(ZipChains, TwoSingleEdgesGiveNoTriangle) {
  const std::vector<Eigen::Vector2d> onA{{1, 0}, {0, 0}}, onB{{0, 0}, {1, 0}};
  EXPECT_TRUE(zipChains({1, 0}, {0, 1}, DomainZipMetric(onA, onB), true).empty());
}

// A quad with three corners in a line: the only fill with area joins the fourth corner to the
// middle one, though the flat diagonal is shorter.
TEST(ZipChains, NeverMakesAFlatTriangle) {
  const std::vector<Eigen::Vector2d> points{{0, 0}, {1, 0}, {2, 0}, {1, 5}};
  const std::vector<int> a{2, 3, 0}, b{0, 1, 2};
  std::vector<Eigen::Vector2d> onA, onB;
  for (int v : a)
    onA.push_back(points[std::size_t(v)]);
  for (int v : b)
    onB.push_back(points[std::size_t(v)]);
  for (bool keepOrientation : {true, false}) {
    const auto triangles = zipChains(a, b, DomainZipMetric(onA, onB), keepOrientation);
    ASSERT_EQ(triangles.size(), 2u);
    for (const auto& t : triangles)
      EXPECT_GT(signedArea(points, t), 1.0);
    expectFillsPolygon(a, b, triangles);
  }
}

// One shared vertex: both chains are whole loops from it back to it, a circle inside a circle
// touching it at (1, 0); no new edge may join the shared vertex to itself.
TEST(ZipChains, LoopsSharingOneVertexFillTheRingBetweenThem) {
  const int n = 12, m = 20;
  std::vector<Eigen::Vector2d> inner, outer;
  for (int k = 0; k <= n; ++k) {  // clockwise, as a patch's boundary
    const double t = -2 * std::numbers::pi * k / n;
    inner.emplace_back(0.5 + 0.5 * std::cos(t), 0.5 * std::sin(t));
  }
  for (int k = 0; k <= m; ++k) {
    const double t = 2 * std::numbers::pi * k / m;
    outer.emplace_back(std::cos(t), std::sin(t));
  }
  std::vector<int> a = ids(0, n + 1), b = ids(n - 1, m + 1);
  a.front() = a.back() = b.front() = b.back() = 0;
  const auto triangles = zipChains(a, b, DomainZipMetric(inner, outer), true);
  ASSERT_EQ(triangles.size(), std::size_t(n + m - 2));
  expectFillsPolygon(a, b, triangles);
  std::vector<Eigen::Vector2d> points{{1, 0}};
  points.insert(points.end(), inner.begin() + 1, inner.end() - 1);
  points.insert(points.end(), outer.begin() + 1, outer.end() - 1);
  for (const auto& t : triangles)
    EXPECT_GT(signedArea(points, t), 0);
}

TEST(ZipChains, RefusesChainsThatDoNotShareTheirEnds) {
  const std::vector<Eigen::Vector2d> onA{{1, 0}, {0, 1}, {0, 0}}, onB{{0, 0}, {1, 0}};
  const DomainZipMetric metric(onA, onB);
  EXPECT_THROW(zipChains({1, 2, 3}, {0, 1}, metric, true), std::invalid_argument);
  EXPECT_THROW(zipChains({1}, {0, 1}, metric, true), std::invalid_argument);
}

}  // namespace
}  // namespace geobrush
