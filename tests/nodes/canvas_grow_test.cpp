#include "canvas_grow.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// An n x n grid of squares over [-1, 1]^2 at z = 0, each split along one diagonal; cells
// listed in `skip` are left out (a hole in the mesh).
MeshPtr planeGrid(int n, const std::set<std::pair<int, int>>& skip = {}) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.add_vertex({-1 + 2.0 * i / n, -1 + 2.0 * j / n, 0});
  auto at = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (skip.count({i, j})) continue;
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return std::make_shared<const Mesh>(std::move(mesh));
}

MeshPtr load(const std::string& name) {
  return readMesh(test::meshPath(name)).mesh;
}

CanvasGrowOptions options(const Eigen::Vector3d& origin, std::vector<CanvasDab> dabs) {
  CanvasGrowOptions o;
  o.origin = origin;
  o.dabs = std::move(dabs);
  return o;
}

struct Failure {
  std::string option;
  std::string message;
};

Failure failure(const MeshPtr& mesh, const CanvasGrowOptions& o) {
  try {
    growCanvas(mesh, o);
  } catch (const CanvasGrowError& e) {
    return {e.option(), e.what()};
  }
  return {"(accepted)", ""};
}

// The canvas is a manifold region with one boundary loop whose maps agree with its source.
void expectValidCanvas(const Canvas& canvas) {
  const TriMesh& surface = canvas.surface;
  const TriMesh& source = canvas.source->surface;
  const test::Topology t = test::topology(surface);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.isolatedVertices, 0u);
  ASSERT_EQ(canvas.sourceVertex.size(), surface.n_vertices());
  ASSERT_EQ(canvas.sourceFace.size(), surface.n_faces());
  EXPECT_TRUE(std::is_sorted(canvas.sourceVertex.begin(), canvas.sourceVertex.end()));
  EXPECT_TRUE(std::is_sorted(canvas.sourceFace.begin(), canvas.sourceFace.end()));
  for (auto v : surface.vertices()) {
    EXPECT_EQ(surface.point(v), source.point(TriMesh::VertexHandle(canvas.sourceVertex[v.idx()])));
  }
  for (auto f : surface.faces()) {
    std::vector<int> mapped, original;
    for (auto v : surface.fv_range(f))
      mapped.push_back(canvas.sourceVertex[v.idx()]);
    for (auto v : source.fv_range(TriMesh::FaceHandle(canvas.sourceFace[f.idx()])))
      original.push_back(v.idx());
    std::rotate(mapped.begin(), std::min_element(mapped.begin(), mapped.end()), mapped.end());
    std::rotate(original.begin(), std::min_element(original.begin(), original.end()),
                original.end());
    EXPECT_EQ(mapped, original) << "face " << f.idx();
  }
  // The boundary is the loop of boundary halfedges, in their order.
  ASSERT_EQ(canvas.boundary.size(), t.boundaryHalfedges);
  for (std::size_t i = 0; i < canvas.boundary.size(); ++i) {
    const auto h = surface.find_halfedge(
        TriMesh::VertexHandle(canvas.boundary[i]),
        TriMesh::VertexHandle(canvas.boundary[(i + 1) % canvas.boundary.size()]));
    ASSERT_TRUE(h.is_valid());
    EXPECT_TRUE(surface.is_boundary(h));
  }
  ASSERT_GE(canvas.originFace, 0);
  ASSERT_LT(canvas.originFace, static_cast<int>(surface.n_faces()));
  bool cornerOfOriginFace = false;
  for (auto v : surface.fv_range(TriMesh::FaceHandle(canvas.originFace)))
    cornerOfOriginFace = cornerOfOriginFace || v.idx() == canvas.originVertex;
  EXPECT_TRUE(cornerOfOriginFace);
  const Eigen::Vector3d originCorner =
      toEigen(surface.point(TriMesh::VertexHandle(canvas.originVertex)));
  for (auto v : surface.fv_range(TriMesh::FaceHandle(canvas.originFace))) {
    EXPECT_LE((originCorner - canvas.originPoint).norm(),
              (toEigen(surface.point(v)) - canvas.originPoint).norm());
  }
  const SurfacePoint onFace = nearestSurfacePoint(surface, canvas.originPoint);
  EXPECT_LE(onFace.distance, 1e-12);
  EXPECT_TRUE(canvas.originPoint.allFinite());
}

long genus(const TriMesh& mesh) {
  const test::Topology t = test::topology(mesh);
  return (2 - t.eulerCharacteristic - static_cast<long>(t.boundaryLoops)) / 2;
}

TEST(CanvasGrow, ClosestPointOnTriangleCoversEveryRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  EXPECT_EQ(closestPointOnTriangle({0.5, 0.5, 3}, a, b, c), Eigen::Vector3d(0.5, 0.5, 0));
  EXPECT_EQ(closestPointOnTriangle({-1, -1, 1}, a, b, c), a);
  EXPECT_EQ(closestPointOnTriangle({3, -1, 0}, a, b, c), b);
  EXPECT_EQ(closestPointOnTriangle({-1, 3, 0}, a, b, c), c);
  EXPECT_EQ(closestPointOnTriangle({1, -2, 0}, a, b, c), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(closestPointOnTriangle({-2, 1, 0}, a, b, c), Eigen::Vector3d(0, 1, 0));
  EXPECT_LE((closestPointOnTriangle({2, 2, 1}, a, b, c) - Eigen::Vector3d(1, 1, 0)).norm(), 1e-15);
}

TEST(CanvasGrow, OneDabOnAPlaneGivesTheDiscOfPaintedFaces) {
  const MeshPtr plane = planeGrid(40);
  const CanvasDab dab{{0.1, 0.05, 0}, 0.5};
  const Canvas canvas = growCanvas(plane, options({0.11, 0.07, 0}, {dab}));
  expectValidCanvas(canvas);
  EXPECT_EQ(genus(canvas.surface), 0);
  EXPECT_EQ(canvas.source, plane);

  // A disc on a grid: its painted faces are connected, so the canvas holds exactly them.
  std::vector<int> expected;
  for (auto f : plane->surface.faces()) {
    bool inside = true;
    for (auto v : plane->surface.fv_range(f))
      inside = inside && (toEigen(plane->surface.point(v)) - dab.center).norm() <= dab.radius;
    if (inside) expected.push_back(f.idx());
  }
  EXPECT_EQ(canvas.sourceFace, expected);
  for (int v : canvas.boundary) {
    EXPECT_LE((toEigen(canvas.surface.point(TriMesh::VertexHandle(v))) - dab.center).norm(),
              dab.radius);
  }
  EXPECT_LE((canvas.originPoint - Eigen::Vector3d(0.11, 0.07, 0)).norm(), 1e-15);
  // The grid's vertex (0.1, 0.05) is the nearest corner.
  EXPECT_LE((toEigen(canvas.surface.point(TriMesh::VertexHandle(canvas.originVertex))) -
             Eigen::Vector3d(0.1, 0.05, 0))
                .norm(),
            1e-15);
}

TEST(CanvasGrow, SnapsTheOriginOntoTheSurface) {
  const Canvas canvas =
      growCanvas(planeGrid(20), options({0.33, -0.21, 0.004}, {{{0.3, -0.2, 0}, 0.4}}));
  EXPECT_LE((canvas.originPoint - Eigen::Vector3d(0.33, -0.21, 0)).norm(), 1e-15);
  expectValidCanvas(canvas);
}

TEST(CanvasGrow, FloodFillStopsAtUnconnectedPaint) {
  // Two separate dabs: only the one under the origin becomes canvas.
  const MeshPtr plane = planeGrid(30);
  const Canvas one = growCanvas(plane, options({-0.5, 0, 0}, {{{-0.5, 0, 0}, 0.3}}));
  const Canvas two =
      growCanvas(plane, options({-0.5, 0, 0}, {{{-0.5, 0, 0}, 0.3}, {{0.5, 0, 0}, 0.3}}));
  EXPECT_EQ(one.sourceFace, two.sourceFace);
  EXPECT_TRUE(test::bitIdentical(one.surface, two.surface));
}

TEST(CanvasGrow, RingOfDabsIsRejectedWithTheHoleToPaint) {
  std::vector<CanvasDab> ring;
  for (int i = 0; i < 24; ++i) {
    const double a = 2 * std::numbers::pi * i / 24;
    ring.push_back({{0.6 * std::cos(a), 0.6 * std::sin(a), 0}, 0.2});
  }
  const Failure f = failure(planeGrid(60), options({0.6, 0, 0}, ring));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "leaves 1 hole inside the canvas (2 boundary loops)"));
  EXPECT_TRUE(test::contains(f.message, "unpainted parts near ("));
  EXPECT_TRUE(test::contains(f.message, "paint over them"));
}

TEST(CanvasGrow, EnclosedHoleOfTheMeshIsRejected) {
  const MeshPtr holed = planeGrid(20, {{9, 9}, {10, 9}, {9, 10}, {10, 10}});
  const Failure f = failure(holed, options({0.5, 0.5, 0}, {{{0, 0, 0}, 0.8}}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "holes of the mesh near ("));
  // Painting up to the mesh's hole without enclosing it is fine: the hole joins the boundary.
  const Canvas canvas = growCanvas(holed, options({0.4, 0.4, 0}, {{{0.3, 0.3, 0}, 0.45}}));
  expectValidCanvas(canvas);
}

TEST(CanvasGrow, CoveringAWholeClosedMeshIsRejected) {
  const Failure f = failure(load("sphere.obj"), options({0, 0, 1}, {{{0, 0, 0}, 2}}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "covers the whole closed surface"));
  EXPECT_TRUE(test::contains(f.message, "leave part of the surface unpainted"));
}

TEST(CanvasGrow, TouchingAtOneVertexIsRejected) {
  // Tiny dabs on chosen grid vertices: the 5 x 5 block around vertex (12, 12) without it and
  // without the corner (10, 10). The painted faces form a ring around (12, 12) cut open at the
  // corner cell, whose two ends still meet at vertex (11, 11).
  const MeshPtr plane = planeGrid(20);
  auto at = [](int i, int j) { return Eigen::Vector3d(-1 + 0.1 * i, -1 + 0.1 * j, 0); };
  std::vector<CanvasDab> dabs;
  for (int j = 10; j <= 14; ++j)
    for (int i = 10; i <= 14; ++i)
      if (!(i == 12 && j == 12) && !(i == 10 && j == 10)) dabs.push_back({at(i, j), 0.01});
  const Failure f = failure(plane, options(at(12, 10), dabs));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(
      test::contains(f.message, "touches itself only at vertex " + std::to_string(11 * 21 + 11)));
}

TEST(CanvasGrow, OriginOffTheSurfaceIsRejected) {
  const Failure f = failure(planeGrid(10), options({0, 0, 0.5}, {{{0, 0, 0}, 0.7}}));
  EXPECT_EQ(f.option, "origin");
  EXPECT_TRUE(test::contains(f.message, "away from the surface"));
  EXPECT_TRUE(test::contains(f.message, "pick a point on the surface"));
}

TEST(CanvasGrow, OriginOnTheMeshBoundaryIsRejected) {
  const MeshPtr mountain = load("mountain.obj");
  const TriMesh& m = mountain->surface;
  TriMesh::VertexHandle corner;
  for (auto v : m.vertices()) {
    if (m.is_boundary(v)) {
      corner = v;
      break;
    }
  }
  ASSERT_TRUE(corner.is_valid());
  const Eigen::Vector3d p = toEigen(m.point(corner));
  const Failure f = failure(mountain, options(p, {{p, 5}}));
  EXPECT_EQ(f.option, "origin");
  EXPECT_TRUE(test::contains(f.message, "boundary loop 0 of 1, 636 edges"));
  EXPECT_TRUE(test::contains(f.message, "near vertex " + std::to_string(corner.idx())));
  // Beyond the boundary, within the tolerance, snaps onto the boundary too.
  const Failure beyond = failure(planeGrid(10), options({1.001, 0.2, 0}, {{{1, 0.2, 0}, 0.5}}));
  EXPECT_EQ(beyond.option, "origin");
  EXPECT_TRUE(test::contains(beyond.message, "boundary loop 0 of 1, 40 edges"));
}

TEST(CanvasGrow, RejectsBadPainting) {
  const MeshPtr plane = planeGrid(10);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Failure f = failure(plane, options({0, 0, 0}, {}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "nothing is painted"));
  f = failure(plane, options({0, 0, 0}, {{{0.5, 0.5, 0}, 0.2}}));
  EXPECT_EQ(f.option, "origin");
  EXPECT_TRUE(test::contains(f.message, "outside every dab"));
  f = failure(plane, options({0, 0, 0}, {{{0, 0, 0}, 0.01}}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "not wholly painted"));
  f = failure(plane, options({0, 0, 0}, {{{0, 0, 0}, -1}}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "radii must be positive"));
  f = failure(plane, options({0, 0, 0}, {{{0, nan, 0}, 1}}));
  EXPECT_EQ(f.option, "dabs");
  EXPECT_TRUE(test::contains(f.message, "non-finite"));
  f = failure(plane, options({0, 0, nan}, {{{0, 0, 0}, 1}}));
  EXPECT_EQ(f.option, "origin");
  f = failure(plane, options({0, 0, 0}, {{{0, 0, 0}, std::numeric_limits<double>::infinity()}}));
  EXPECT_EQ(f.option, "dabs");
}

TEST(CanvasGrow, RejectsZeroAreaFacesInTheRegion) {
  TriMesh mesh = planeGrid(10)->surface;
  // Move a vertex onto the line of two neighbours: the faces between collapse.
  const auto v = TriMesh::VertexHandle(5 * 11 + 5);
  mesh.point(v) = (mesh.point(TriMesh::VertexHandle(5 * 11 + 4)) +
                   mesh.point(TriMesh::VertexHandle(6 * 11 + 5))) /
                  2;
  const Failure f =
      failure(std::make_shared<const Mesh>(mesh), options({0.5, 0.5, 0}, {{{0, 0, 0}, 0.9}}));
  EXPECT_EQ(f.option, "mesh");
  EXPECT_TRUE(test::contains(f.message, "zero-area face"));
}

// Paints all of a mesh but a cap at its extreme in direction `d`: one ball from far away on
// the other side, reaching to `depth` short of the farthest vertex.
CanvasGrowOptions allButACap(const TriMesh& mesh, const Eigen::Vector3d& d, double depth) {
  const Eigen::Vector3d center = -1000 * d;
  double farthest = 0, nearest = std::numeric_limits<double>::infinity();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = toEigen(mesh.point(v));
    farthest = std::max(farthest, (p - center).norm());
    if ((p - center).norm() < nearest) {
      nearest = (p - center).norm();
      origin = p;
    }
  }
  return options(origin, {{center, farthest - depth}});
}

TEST(CanvasGrow, KeepsTheHandleOfATorus) {
  const MeshPtr torus = load("torus.obj");
  const Canvas canvas = growCanvas(torus, allButACap(torus->surface, {1, 0, 0}, 0.05));
  expectValidCanvas(canvas);
  EXPECT_EQ(genus(canvas.surface), 1);
  EXPECT_LT(canvas.surface.n_faces(), torus->surface.n_faces());
}

TEST(CanvasGrow, KeepsTheHandleOfTheKnot) {
  const MeshPtr knot = load("knot.obj");
  const Canvas canvas = growCanvas(
      knot, allButACap(knot->surface, Eigen::Vector3d(0.3, 0.5, 0.8).normalized(), 0.05));
  expectValidCanvas(canvas);
  EXPECT_EQ(genus(canvas.surface), 1);
}

TEST(CanvasGrow, RealMeshesGiveValidCanvases) {
  for (const auto& [name, vertex, radius] :
       {std::tuple{"bunny_small.obj", 100, 0.08}, std::tuple{"bunny_small.obj", 1000, 0.12},
        std::tuple{"armadillo.obj", 5000, 0.04}, std::tuple{"armadillo.obj", 12000, 0.05}}) {
    SCOPED_TRACE(std::string(name) + " vertex " + std::to_string(vertex));
    const MeshPtr mesh = load(name);
    const TriMesh& m = mesh->surface;
    const Eigen::Vector3d p = toEigen(m.point(TriMesh::VertexHandle(vertex)));
    Eigen::Vector3d lo = p, hi = p;
    for (auto v : m.vertices()) {
      lo = lo.cwiseMin(toEigen(m.point(v)));
      hi = hi.cwiseMax(toEigen(m.point(v)));
    }
    const double r = radius * (hi - lo).norm();
    const Eigen::Vector3d t = Eigen::Vector3d(1, 2, 2) / 3;
    // A stroke of three overlapping dabs.
    const std::vector<CanvasDab> dabs = {
        {p, r}, {p + 0.5 * r * t, 0.8 * r}, {p - 0.5 * r * t, 0.8 * r}};
    const Canvas canvas = growCanvas(mesh, options(p, dabs));
    expectValidCanvas(canvas);
    EXPECT_GT(canvas.surface.n_faces(), 10u);
    EXPECT_EQ(canvas.sourceVertex[canvas.originVertex], vertex);
    const Canvas again = growCanvas(mesh, options(p, dabs));
    EXPECT_TRUE(test::bitIdentical(canvas.surface, again.surface));
    EXPECT_EQ(canvas.boundary, again.boundary);
    EXPECT_EQ(canvas.sourceFace, again.sourceFace);
  }
}

using test::DirectContext;

TEST(CanvasGrowNode, ComputesTheAlgorithmsCanvas) {
  const NodeType* type = test::registry().find("geobrush.canvas_grow");
  ASSERT_NE(type, nullptr);
  const MeshPtr plane = planeGrid(20);
  DirectContext ctx(*type, {{"mesh", plane}},
                    {{"origin", Vec3{0.1, 0.1, 0}},
                     {"dabs", std::vector<double>{0.1, 0.1, 0, 0.4, 0.3, 0.1, 0, 0.3}}});
  type->create()->compute(ctx);
  EXPECT_TRUE(ctx.warnings.empty());
  const auto canvas = std::dynamic_pointer_cast<const Canvas>(ctx.outputs["canvas"]);
  ASSERT_NE(canvas, nullptr);
  const Canvas direct =
      growCanvas(plane, options({0.1, 0.1, 0}, {{{0.1, 0.1, 0}, 0.4}, {{0.3, 0.1, 0}, 0.3}}));
  EXPECT_TRUE(test::bitIdentical(canvas->surface, direct.surface));
  EXPECT_EQ(canvas->boundary, direct.boundary);
  EXPECT_EQ(canvas->contentHash(), std::make_shared<const Canvas>(direct)->contentHash());
}

std::string nodeError(const ParamMap& params, const MeshPtr& mesh) {
  const NodeType* type = test::registry().find("geobrush.canvas_grow");
  DirectContext ctx(*type, {{"mesh", mesh}}, params);
  try {
    type->create()->compute(ctx);
    EXPECT_TRUE(ctx.warnings.empty());
  } catch (const NodeError& e) {
    return e.where() + ": " + e.what();
  }
  return "(accepted)";
}

TEST(CanvasGrowNode, ErrorsNameTheParam) {
  const MeshPtr plane = planeGrid(10);
  EXPECT_TRUE(test::contains(nodeError({}, plane), "param 'dabs': nothing is painted"));
  EXPECT_TRUE(test::contains(
      nodeError({{"origin", Vec3{0, 0, 3}}, {"dabs", std::vector<double>{0, 0, 0, 1}}}, plane),
      "param 'origin': "));
  TriMesh broken = plane->surface;
  broken.point(TriMesh::VertexHandle(3))[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(test::contains(
      nodeError({{"dabs", std::vector<double>{0, 0, 0, 1}}}, std::make_shared<const Mesh>(broken)),
      "input 'mesh': vertex 3"));
}

TEST(CanvasGrowNode, RunsInAGraphAfterAPrimitive) {
  Graph graph;
  graph.nodes["plane"] = {
      "geobrush.primitive", 1, {{"shape", std::string("plane")}, {"resolution", std::int64_t{16}}}};
  graph.nodes["canvas"] = {
      "geobrush.canvas_grow",
      1,
      {{"origin", Vec3{0.05, 0.02, 0}}, {"dabs", std::vector<double>{0, 0, 0, 0.3}}}};
  graph.connections.push_back({{"plane", "mesh"}, {"canvas", "mesh"}});
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  const auto canvas = std::dynamic_pointer_cast<const Canvas>(evaluator.output("canvas", "canvas"));
  ASSERT_NE(canvas, nullptr);
  expectValidCanvas(*canvas);

  graph.nodes["canvas"].params["origin"] = Vec3{0, 0, 1};
  const EvalReport off = evaluator.evaluate(graph);
  EXPECT_FALSE(off.ok);
  EXPECT_TRUE(test::contains(off.error, "param 'origin'"));
}

}  // namespace
}  // namespace geobrush
