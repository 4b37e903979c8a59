#include "min_area_triangulate.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;
using Triangles = std::vector<std::array<int, 3>>;

Vector3d faceNormal(const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::vector<Vector3d> c;
  for (auto v : mesh.fv_range(f))
    c.push_back(pointOf(mesh, v.idx()));
  return (c[1] - c[0]).cross(c[2] - c[0]);
}

// Twice the vector area: the same for every surface a loop bounds, the sign its orientation's.
Vector3d vectorArea(const TriMesh& mesh) {
  Vector3d sum = Vector3d::Zero();
  for (auto f : mesh.faces())
    sum += faceNormal(mesh, f);
  return sum;
}

// The polygon (x_i, y_i) placed in a tilted plane through (1, 2, 3).
std::vector<Vector3d> inTiltedPlane(const std::vector<Eigen::Vector2d>& polygon) {
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vector3d(1, 2, 0.5).normalized())).toRotationMatrix();
  std::vector<Vector3d> loop;
  for (const auto& p : polygon)
    loop.push_back(turn * Vector3d(p.x(), p.y(), 0) + Vector3d(1, 2, 3));
  return loop;
}

double shoelaceArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * std::abs(twice);
}

double costOf(const std::vector<Vector3d>& loop, const Triangles& triangles,
              TriangulationObjective objective) {
  double sum = 0;
  for (const auto& t : triangles)
    sum += triangleCost(loop[t[0]], loop[t[1]], loop[t[2]], objective);
  return sum;
}

// Every triangulation of the polygon i..j (its chord i-j closing it), listed one by one.
std::vector<Triangles> allTriangulations(int i, int j) {
  if (j - i < 2) return {Triangles{}};
  std::vector<Triangles> all;
  for (int k = i + 1; k < j; ++k)
    for (const auto& left : allTriangulations(i, k))
      for (const auto& right : allTriangulations(k, j)) {
        Triangles t = left;
        t.insert(t.end(), right.begin(), right.end());
        t.push_back({i, j, k});
        all.push_back(std::move(t));
      }
  return all;
}

// A canvas whose surface is a fan from one centre vertex (index n) over `loop`, with boundary
// halfedges running i -> i + 1.
Canvas fanCanvas(const std::vector<Vector3d>& loop) {
  Canvas canvas;
  const int n = int(loop.size());
  Vector3d centre = Vector3d::Zero();
  for (const auto& p : loop) {
    canvas.surface.add_vertex(toPoint(p));
    centre += p / n;
  }
  canvas.surface.add_vertex(toPoint(centre));
  for (int i = 0; i < n; ++i)
    canvas.surface.add_face(TriMesh::VertexHandle(n), TriMesh::VertexHandle((i + 1) % n),
                            TriMesh::VertexHandle(i));
  for (int i = 0; i < n; ++i)
    canvas.boundary.push_back(i);
  return canvas;
}

std::vector<Eigen::Vector2d> regularPolygon(int n, double rx, double ry) {
  std::vector<Eigen::Vector2d> polygon;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n;
    polygon.emplace_back(rx * std::cos(angle), ry * std::sin(angle));
  }
  return polygon;
}

TEST(MinAreaTriangulate, AConvexPlanarPolygonGivesItsShoelaceArea) {
  const auto polygon = regularPolygon(17, 2.0, 0.7);
  const auto loop = inTiltedPlane(polygon);
  const auto t = optimalTriangulation(loop, TriangulationObjective::Area);
  EXPECT_EQ(t.triangles.size(), 15u);
  EXPECT_NEAR(t.cost, shoelaceArea(polygon), 1e-13 * shoelaceArea(polygon));
  EXPECT_NEAR(costOf(loop, t.triangles, TriangulationObjective::Area), t.cost, 1e-13 * t.cost);
}

// A star and a comb: any triangulation's areas sum to at least the shoelace area, with equality
// only for one that covers the polygon once (no face outside it, no two overlapping).
TEST(MinAreaTriangulate, NonConvexPlanarPolygonsGiveTheirShoelaceArea) {
  std::vector<Eigen::Vector2d> star;
  for (int i = 0; i < 14; ++i) {
    const double angle = 2 * M_PI * i / 14, r = i % 2 ? 0.35 : 1.0;
    star.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  // No three corners on a line, so no face of zero area can tie.
  const std::vector<Eigen::Vector2d> comb{{0, 0},   {5, 0}, {5, 3},   {4, 3.2}, {4, 1},   {3, 1.3},
                                          {3, 3.1}, {2, 3}, {2, 1.1}, {1, 1.4}, {1, 2.9}, {0, 3.3}};
  for (const auto& polygon : {star, comb}) {
    const auto loop = inTiltedPlane(polygon);
    const auto t = optimalTriangulation(loop, TriangulationObjective::Area);
    const double area = shoelaceArea(polygon);
    EXPECT_NEAR(t.cost, area, 1e-12 * area);
    // Every face turns the same way: the base covers the polygon once.
    const TriMesh base = triangulationMesh(loop, t);
    const Vector3d side = vectorArea(base).normalized();
    for (auto f : base.faces())
      EXPECT_GT(faceNormal(base, f).dot(side), 0.0) << f.idx();
  }
}

// A region of a grid is bounded by runs of collinear mesh edges: a triangle over three corners of
// one run has no area, so it would tie with the real triangles, yet it folds onto them.
TEST(MinAreaTriangulate, CollinearRunsOfAGridOutlineGetNoDegenerateTriangle) {
  std::vector<Eigen::Vector2d> staircase;
  for (int i = 0; i <= 6; ++i)
    staircase.emplace_back(i, 0);
  for (int j = 1; j <= 3; ++j)
    staircase.emplace_back(6, j);
  for (const auto& [x, y] :
       {std::pair{5, 3}, {4, 3}, {4, 4}, {3, 4}, {2, 4}, {2, 5}, {1, 5}, {0, 5}})
    staircase.emplace_back(x, y);
  for (int j = 4; j >= 1; --j)
    staircase.emplace_back(0, j);
  const auto loop = inTiltedPlane(staircase);
  const auto t = optimalTriangulation(loop, TriangulationObjective::Area);
  EXPECT_EQ(t.degenerate, 0u);
  const double area = shoelaceArea(staircase);
  EXPECT_NEAR(t.cost, area, 1e-12 * area);
  const TriMesh base = triangulationMesh(loop, t);
  const Vector3d side = vectorArea(base).normalized();
  for (auto f : base.faces())
    EXPECT_GT(faceNormal(base, f).dot(side), 1e-9) << f.idx();
  std::vector<int> faces(base.n_faces());
  std::iota(faces.begin(), faces.end(), 0);
  EXPECT_EQ(selfIntersections(base, faces, 1e-12 * boundingDiagonal(base)), 0u);
}

TEST(MinAreaTriangulate, MatchesBruteForceOverAllTriangulationsOfSpacePolygons) {
  std::mt19937 random(20240611);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  int checked = 0;
  for (int n = 3; n <= 10; ++n) {
    const auto all = allTriangulations(0, n - 1);
    for (int trial = 0; trial < 4; ++trial) {
      std::vector<Vector3d> loop(static_cast<std::size_t>(n), Vector3d::Zero());
      for (auto& p : loop)
        p = Vector3d(coordinate(random), coordinate(random), coordinate(random));
      for (auto objective : {TriangulationObjective::Area, TriangulationObjective::Perimeter}) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& triangles : all)
          best = std::min(best, costOf(loop, triangles, objective));
        const auto t = optimalTriangulation(loop, objective);
        ASSERT_EQ(t.triangles.size(), std::size_t(n - 2));
        EXPECT_NEAR(t.cost, best, 1e-12 * best) << "n " << n;
        EXPECT_NEAR(costOf(loop, t.triangles, objective), t.cost, 1e-12 * best) << "n " << n;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 64);
}

// A square's two triangulations have the same area and perimeter: the one through split vertex
// 1 wins. The sum of perimeters is the loop's length plus twice the diagonal.
TEST(MinAreaTriangulate, TiesGoToTheSmallestSplitVertex) {
  const std::vector<Vector3d> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (auto objective : {TriangulationObjective::Area, TriangulationObjective::Perimeter}) {
    const auto t = optimalTriangulation(square, objective);
    const Triangles expected{{0, 3, 1}, {1, 3, 2}};
    EXPECT_EQ(t.triangles, expected);
    EXPECT_DOUBLE_EQ(t.cost, objective == TriangulationObjective::Area ? 1.0 : 4 + 2 * M_SQRT2);
  }
}

// Boundary halfedges of the base run i -> i + 1: a loop running counter-clockwise seen from +z
// gets faces facing -z (cut_paste.hpp's convention, the surface lying to the right of the loop).
TEST(MinAreaTriangulate, BoundaryHalfedgesRunAlongTheLoop) {
  const auto polygon = regularPolygon(9, 1.0, 1.0);
  std::vector<Vector3d> loop;
  for (const auto& p : polygon)
    loop.emplace_back(p.x(), p.y(), 0.1 * p.x() * p.y());
  const TriMesh base = triangulationMesh(loop, optimalTriangulation(loop, {}));
  for (int i = 0; i < 9; ++i) {
    const auto h = base.find_halfedge(TriMesh::VertexHandle(i), TriMesh::VertexHandle((i + 1) % 9));
    ASSERT_TRUE(h.is_valid());
    EXPECT_TRUE(base.is_boundary(h)) << i;
  }
  for (auto f : base.faces())
    EXPECT_LT(faceNormal(base, f).z(), 0.0) << f.idx();
}

struct RealCanvas {
  MeshPtr mesh;
  Canvas canvas;
};

RealCanvas realCanvas(const std::string& file, const Vector3d& near, double radius) {
  RealCanvas r;
  r.mesh = readMesh(test::meshPath(file)).mesh;
  const TriMesh& m = r.mesh->surface;
  int nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (auto f : m.faces()) {
    Vector3d centroid = Vector3d::Zero();
    for (auto v : m.fv_range(f))
      centroid += pointOf(m, v.idx()) / 3;
    if ((centroid - near).norm() < best) {
      best = (centroid - near).norm();
      nearest = f.idx();
    }
  }
  r.canvas = test::growDiscCanvas(r.mesh, nearest, radius);
  return r;
}

// B0 over a canvas: n - 2 faces, a disc on the canvas's loop at its positions, with the
// canvas's orientation (equal vector areas: both span the same loop).
void expectBaseOverCanvas(const TriMesh& base, const Canvas& canvas) {
  const std::size_t n = canvas.boundary.size();
  ASSERT_EQ(base.n_vertices(), n);
  EXPECT_EQ(base.n_faces(), n - 2);
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_EQ(base.point(TriMesh::VertexHandle(int(i))),
              canvas.surface.point(TriMesh::VertexHandle(canvas.boundary[i])));
  const auto topo = test::topology(base);
  EXPECT_EQ(topo.boundaryLoops, 1u);
  EXPECT_EQ(topo.components, 1u);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(topo.eulerCharacteristic, 1);
  const Vector3d baseArea = vectorArea(base), canvasArea = vectorArea(canvas.surface);
  EXPECT_LT((baseArea - canvasArea).norm(), 1e-12 * canvasArea.norm());
}

// On a cap of the unit sphere the base is a chord surface under the cap, facing outward like it.
TEST(MinAreaTriangulate, ASphereCapGetsAnOutwardChordSurface) {
  const auto r = realCanvas("sphere.obj", Vector3d(0.3, 0.5, 0.81), 0.7);
  const auto result = minAreaTriangulate(r.canvas, MinAreaOptions{});
  ASSERT_GT(r.canvas.boundary.size(), 12u);
  expectBaseOverCanvas(result.base, r.canvas);
  EXPECT_EQ(result.selfIntersections, 0u);
  for (auto f : result.base.faces()) {
    Vector3d centroid = Vector3d::Zero();
    for (auto v : result.base.fv_range(f))
      centroid += pointOf(result.base, v.idx()) / 3;
    EXPECT_GT(faceNormal(result.base, f).dot(centroid), 0.0) << f.idx();  // outward
    EXPECT_LT(centroid.norm(), 1.0);                                      // under the cap
  }
  // The chord surface spans less area than the cap, and no more than any other triangulation
  // of the loop: the fan from vertex 0, say.
  EXPECT_LT(result.area, test::surfaceArea(r.canvas.surface));
  EXPECT_DOUBLE_EQ(result.objective, result.area);
  const std::size_t n = r.canvas.boundary.size();
  Triangles fan;
  std::vector<Vector3d> loop;
  for (int v : r.canvas.boundary)
    loop.push_back(pointOf(r.canvas.surface, v));
  for (int k = 1; k + 1 < int(n); ++k)
    fan.push_back({0, k + 1, k});
  EXPECT_LE(result.area, costOf(loop, fan, TriangulationObjective::Area));
}

// Each objective's base is the best under its own measure: the area objective's has no more
// area than the perimeter objective's, which has no longer interior edges.
TEST(MinAreaTriangulate, ABunnyRegionGetsADiscOrientedLikeIt) {
  const auto r = realCanvas("bunny_small.obj", Vector3d(0, 5, 3.5), 2.5);
  ASSERT_GT(r.canvas.boundary.size(), 40u);
  MinAreaResult best[2];
  for (auto objective : {TriangulationObjective::Area, TriangulationObjective::Perimeter}) {
    MinAreaOptions options;
    options.objective = objective;
    auto& result = best[int(objective)];
    result = minAreaTriangulate(r.canvas, options);
    expectBaseOverCanvas(result.base, r.canvas);
    EXPECT_EQ(result.selfIntersections, 0u);
  }
  const auto& byArea = best[int(TriangulationObjective::Area)];
  const auto& byPerimeter = best[int(TriangulationObjective::Perimeter)];
  EXPECT_DOUBLE_EQ(byArea.objective, byArea.area);
  EXPECT_LE(byArea.area, byPerimeter.area);
  EXPECT_LE(byPerimeter.interiorEdgeLength, byArea.interiorEdgeLength);
  {
    std::ostringstream measured;
    measured << "bunny loop " << r.canvas.boundary.size() << ": area " << byArea.area << " vs "
             << byPerimeter.area << ", interior edges " << byArea.interiorEdgeLength << " vs "
             << byPerimeter.interiorEdgeLength;
    RecordProperty("measured", measured.str());
  }
}

const NodeType& nodeType() {
  const NodeType* type = test::registry().find("geobrush.min_area_triangulate");
  EXPECT_NE(type, nullptr);
  return *type;
}

TEST(MinAreaTriangulateNode, OutputsTheBaseAndItsReport) {
  const auto r = realCanvas("sphere.obj", Vector3d(0.3, 0.5, 0.81), 0.7);
  auto canvas = std::make_shared<const Canvas>(r.canvas);
  for (const std::string objective : {"area", "perimeter"}) {
    test::DirectContext ctx(nodeType(), {{"canvas", canvas}}, {{"objective", objective}});
    nodeType().create()->compute(ctx);
    const auto base = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["base"]);
    const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
    ASSERT_TRUE(base && report);
    expectBaseOverCanvas(base->surface, r.canvas);
    EXPECT_TRUE(ctx.warnings.empty());
    const double n = double(r.canvas.boundary.size());
    EXPECT_EQ(report->values.at("loop_vertices"), n);
    EXPECT_EQ(report->values.at("triangles"), n - 2);
    EXPECT_EQ(report->values.at("self_intersections"), 0.0);
    double loopLength = 0;
    for (std::size_t i = 0; i < r.canvas.boundary.size(); ++i)
      loopLength +=
          (pointOf(base->surface, int(i)) - pointOf(base->surface, int((i + 1) % std::size_t(n))))
              .norm();
    if (objective == "area")
      EXPECT_DOUBLE_EQ(report->values.at("objective"), report->values.at("area"));
    else
      EXPECT_NEAR(report->values.at("objective"),
                  loopLength + 2 * report->values.at("interior_edge_length"), 1e-12 * loopLength);
  }
}

// A loop wound twice around an axis bounds no surface without folds: the base's faces overlap.
TEST(MinAreaTriangulateNode, WarnsWhereTheBaseIntersectsItself) {
  std::vector<Vector3d> loop;
  for (int i = 0; i < 24; ++i) {
    const double angle = 4 * M_PI * i / 24, radius = 1 + 0.4 * i / 24;
    loop.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.05 * std::sin(angle));
  }
  auto canvas = std::make_shared<const Canvas>(fanCanvas(loop));
  test::DirectContext ctx(nodeType(), {{"canvas", canvas}});
  nodeType().create()->compute(ctx);
  const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
  ASSERT_TRUE(report);
  const double pairs = report->values.at("self_intersections");
  EXPECT_GT(pairs, 0.0);
  ASSERT_EQ(ctx.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(ctx.warnings[0], std::to_string(int(pairs)) + " pairs"));
}

TEST(MinAreaTriangulateNode, RefusesLoopsTooShortTooLongOrAgainstTheSurface) {
  auto expectRefusal = [](const Canvas& canvas, const std::string& part) {
    auto value = std::make_shared<const Canvas>(canvas);
    test::DirectContext ctx(nodeType(), {{"canvas", value}});
    try {
      nodeType().create()->compute(ctx);
      ADD_FAILURE() << "accepted a canvas that should fail with " << part;
    } catch (const NodeError& e) {
      EXPECT_EQ(e.where(), "input 'canvas'");
      EXPECT_TRUE(test::contains(e.what(), part));
    }
  };
  std::vector<Vector3d> triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Canvas shortLoop = fanCanvas(triangle);
  shortLoop.boundary = {0, 1};
  expectRefusal(shortLoop, "has 2 vertices; a base needs at least 3");

  std::vector<Vector3d> circle;
  for (int i = 0; i < 2001; ++i)
    circle.emplace_back(std::cos(2 * M_PI * i / 2001), std::sin(2 * M_PI * i / 2001), 0);
  expectRefusal(fanCanvas(circle), "has 2001 vertices; the triangulation takes at most 2000");

  Canvas reversed = fanCanvas(triangle);
  std::reverse(reversed.boundary.begin(), reversed.boundary.end());
  expectRefusal(reversed, "does not run along the surface's boundary halfedges");
  Canvas outside = fanCanvas(triangle);
  outside.boundary[2] = 7;
  expectRefusal(outside, "names vertex 7");
}

}  // namespace
}  // namespace geobrush
