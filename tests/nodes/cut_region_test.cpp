// geobrush.cut_region: the painted region removed, the rest one manifold piece with one new loop.
#include "cut_region.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The flat grid [-1, 1]^2 of n x n quads, each split by its (i, j)-(i+1, j+1) diagonal into
// faces 2 (j n + i) and 2 (j n + i) + 1.
TriMesh flatGrid(int n) {
  return test::heightGrid(n, [](double, double) { return 0.0; })->surface;
}

// Flags the vertices for which `inside` holds.
std::vector<char> paint(const TriMesh& mesh,
                        const std::function<bool(const Eigen::Vector3d&)>& inside) {
  std::vector<char> painted;
  for (const auto v : mesh.vertices())
    painted.push_back(inside(pointOf(mesh, v)) ? 1 : 0);
  return painted;
}

CutRegionResult cutPainted(const TriMesh& mesh, std::vector<char> painted) {
  CutRegionOptions options;
  options.painted = std::move(painted);
  return cutRegion(mesh, options);
}

std::size_t count(const std::vector<char>& flags) {
  return std::size_t(std::count(flags.begin(), flags.end(), 1));
}

// The faces of `mesh` with a corner that `painted` flags.
std::vector<int> facesTouching(const TriMesh& mesh, const std::vector<char>& painted) {
  std::vector<int> faces;
  for (const auto f : mesh.faces())
    for (const auto v : mesh.fv_range(f))
      if (painted[std::size_t(v.idx())]) {
        faces.push_back(f.idx());
        break;
      }
  return faces;
}

// One manifold component whose boundary loops are `loops`, with the given Euler characteristic,
// and the border a boundary loop of it.
void expectManifoldPiece(const CutRegionResult& r, std::size_t loops, long euler) {
  const test::Topology t = test::topology(r.mesh);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.isolatedVertices, 0u);
  EXPECT_EQ(t.boundaryLoops, loops);
  EXPECT_EQ(t.eulerCharacteristic, euler);
  EXPECT_EQ(borderLoopProblem(r.mesh, r.border), "");
}

// Faces as vertex triples rotated to start at their lowest vertex: what a face is, whatever corner
// OpenMesh starts it from.
std::vector<std::array<int, 3>> canonicalFaces(const TriMesh& mesh) {
  auto faces = test::faceIndices(mesh);
  for (auto& f : faces)
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return faces;
}

std::vector<Eigen::Vector3d> points(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> p;
  for (const auto v : mesh.vertices())
    p.push_back(pointOf(mesh, v));
  return p;
}

MeshPtr loaded(const std::string& name) {
  return readMesh(test::meshPath(name)).mesh;
}

MeshPtr primitive(const std::string& shape, int resolution) {
  const auto run = test::runNode("geobrush.primitive", {},
                                 {{"shape", shape}, {"resolution", std::int64_t(resolution)}});
  return run.get<Mesh>("mesh");
}

}  // namespace

// A disc painted on a flat grid: exactly the painted vertices go, with the faces around them; the
// border is the ring of unpainted vertices next to them, and the grid becomes an annulus (chi 0).
TEST(CutRegion, FlatGridDiscRemovesExactlyThePaintedVertices) {
  const int n = 20;  // spacing 0.1: vertex distances are 0.1 sqrt(i^2 + j^2), never 0.35
  const TriMesh grid = flatGrid(n);
  const auto painted = paint(grid, [](const Eigen::Vector3d& p) { return p.norm() < 0.35; });
  const CutRegionResult r = cutPainted(grid, painted);

  // 1 + 4 (1 + 2 + 3) + 4 (2 + 2 + 1 + 1 + ...) = the lattice points with i^2 + j^2 <= 12.
  EXPECT_EQ(count(painted), 37u);
  EXPECT_EQ(r.paintedVertices, 37u);
  EXPECT_EQ(grid.n_vertices() - r.mesh.n_vertices(), 37u);
  EXPECT_EQ(r.removedFace, facesTouching(grid, painted));
  EXPECT_EQ(r.cleanedFaces, 0u);
  for (std::size_t k = 0; k < r.keptVertex.size(); ++k) {
    EXPECT_FALSE(painted[std::size_t(r.keptVertex[k])]);
    EXPECT_EQ(pointOf(r.mesh, int(k)), pointOf(grid, r.keptVertex[k]));
  }
  expectManifoldPiece(r, 2, 0);

  std::set<int> ring;  // unpainted neighbours of painted vertices, as input indices
  for (const auto v : grid.vertices())
    if (!painted[std::size_t(v.idx())])
      for (const auto w : grid.vv_range(v))
        if (painted[std::size_t(w.idx())]) ring.insert(v.idx());
  std::set<int> border;
  for (int b : r.border)
    border.insert(r.keptVertex[std::size_t(b)]);
  EXPECT_EQ(border, ring);
  EXPECT_EQ(r.border.size(), ring.size());
  EXPECT_EQ(r.border.front(), *std::min_element(r.border.begin(), r.border.end()));

  // The removed patch is the disc of removed faces with their corners, in input order.
  EXPECT_EQ(r.removed.n_faces(), r.removedFace.size());
  EXPECT_EQ(test::topology(r.removed).eulerCharacteristic, 1);
  EXPECT_TRUE(std::is_sorted(r.removedVertex.begin(), r.removedVertex.end()));
}

// A cap of the primitive sphere: the rest is a disc (chi 1) whose border lies just below the cap,
// and the two parts share the sphere's area.
TEST(CutRegion, SphereCapLeavesADisc) {
  const MeshPtr sphere = primitive("sphere", 16);
  ASSERT_TRUE(sphere);
  const TriMesh& mesh = sphere->surface;
  const double cut = std::cos(35 * M_PI / 180);
  const auto painted =
      paint(mesh, [&](const Eigen::Vector3d& p) { return p.z() > cut * p.norm(); });
  ASSERT_GT(count(painted), 10u);
  const CutRegionResult r = cutPainted(mesh, painted);
  expectManifoldPiece(r, 1, 1);
  EXPECT_EQ(r.cleanedFaces, 0u);
  EXPECT_EQ(r.removedFace, facesTouching(mesh, painted));
  EXPECT_EQ(mesh.n_vertices() - r.mesh.n_vertices(), count(painted));
  EXPECT_EQ(test::topology(r.removed).eulerCharacteristic, 1);
  for (int b : r.border) {
    const Eigen::Vector3d p = pointOf(r.mesh, b);
    EXPECT_LE(p.z(), cut * p.norm());
    EXPECT_GT(p.z(), 0.5 * cut * p.norm());  // next to the cap, not elsewhere
  }
  EXPECT_NEAR(test::surfaceArea(r.mesh) + test::surfaceArea(r.removed), test::surfaceArea(mesh),
              1e-12 * test::surfaceArea(mesh));
}

// A painted ring cuts off the disc inside it: the island goes with the ring, one loop is left.
TEST(CutRegion, IslandInsideTheRegionIsRemoved) {
  const TriMesh grid = flatGrid(24);
  const auto painted =
      paint(grid, [](const Eigen::Vector3d& p) { return p.norm() > 0.3 && p.norm() < 0.5; });
  const CutRegionResult r = cutPainted(grid, painted);
  expectManifoldPiece(r, 2, 0);
  // Kept: the faces with every corner outside the ring's outer circle.
  std::vector<int> outside;
  for (const auto f : grid.faces())
    if (std::all_of(grid.cfv_begin(f), grid.cfv_end(f),
                    [&](auto v) { return pointOf(grid, v).norm() >= 0.5; }))
      outside.push_back(f.idx());
  EXPECT_EQ(r.keptFace, outside);
  EXPECT_GT(r.cleanedFaces, 0u);
  EXPECT_EQ(r.cleanedFaces, r.removedFace.size() - facesTouching(grid, painted).size());
  for (int b : r.border)
    EXPECT_LT(pointOf(r.mesh, b).norm(), 0.65);
}

// Two painted vertices two apart on a row leave the vertex between them with one kept face above
// and one below (a bow-tie): the wedge with the lower face stays, the other goes.
TEST(CutRegion, BowTieKeepsTheWedgeWithTheLowestFace) {
  const int n = 10, i = 4, j = 5;
  const TriMesh grid = flatGrid(n);
  std::vector<char> painted(grid.n_vertices(), 0);
  painted[std::size_t(j * (n + 1) + i)] = 1;
  painted[std::size_t(j * (n + 1) + i + 2)] = 1;
  const CutRegionResult r = cutPainted(grid, painted);
  EXPECT_EQ(r.paintedFaces, 12u);
  EXPECT_EQ(r.cleanedFaces, 1u);
  const int upper = 2 * (j * n + i + 1) + 1;  // (i+1, j), (i+2, j+1), (i+1, j+1)
  const int lower = 2 * ((j - 1) * n + i);    // (i, j-1), (i+1, j-1), (i+1, j)
  EXPECT_TRUE(std::binary_search(r.removedFace.begin(), r.removedFace.end(), upper));
  EXPECT_TRUE(std::binary_search(r.keptFace.begin(), r.keptFace.end(), lower));
  expectManifoldPiece(r, 2, 0);
}

// A ring around the torus' tube opens it into a tube with two new loops: refused, naming strokes.
TEST(CutRegion, RingAroundAHandleIsRefused) {
  const MeshPtr torus = primitive("torus", 32);
  ASSERT_TRUE(torus);
  const auto painted = paint(
      torus->surface, [](const Eigen::Vector3d& p) { return p.x() > 0 && std::abs(p.y()) < 0.12; });
  try {
    cutPainted(torus->surface, painted);
    FAIL() << "a cut through the tube was accepted";
  } catch (const CutRegionError& e) {
    EXPECT_EQ(e.port(), "strokes");
    EXPECT_NE(std::string(e.what()).find("2 boundary loops"), std::string::npos) << e.what();
  }
}

// bunny_small's back hole case, painted: its removed vertices. Its protocol also removed face 851,
// which has none of them as a corner (its corners stay, on the ring around the hole); removing the
// faces around painted vertices keeps it, which leaves a 17-vertex border where the case has 18.
// Everything else is the case's hole mesh and removed patch, element for element.
TEST(CutRegion, ReproducesTheBunnySmallBackHoleCase) {
  std::ifstream file(test::meshPath("cases/bunny_small_back_hole.json"));
  const nlohmann::json spec = nlohmann::json::parse(file);
  const MeshPtr bunny = loaded("bunny_small.obj");
  std::vector<char> painted(bunny->surface.n_vertices(), 0);
  for (int v : spec["removed_vertex_indices_0based"].get<std::vector<int>>())
    painted[std::size_t(v)] = 1;
  const CutRegionResult r = cutPainted(bunny->surface, painted);
  auto caseFaces = spec["removed_face_indices_0based"].get<std::vector<int>>();
  const int unpaintedFace = 851;
  ASSERT_TRUE(std::binary_search(caseFaces.begin(), caseFaces.end(), unpaintedFace));
  caseFaces.erase(std::find(caseFaces.begin(), caseFaces.end(), unpaintedFace));
  EXPECT_EQ(r.removedFace, caseFaces);
  EXPECT_EQ(r.cleanedFaces, 0u);
  expectManifoldPiece(r, 1, 1);
  EXPECT_EQ(r.border.size(), 17u);

  const MeshPtr hole = loaded("cases/bunny_small_back_hole.obj");
  EXPECT_EQ(points(r.mesh), points(hole->surface));
  auto faces = canonicalFaces(r.mesh);
  const auto at = std::find(r.keptFace.begin(), r.keptFace.end(), unpaintedFace);
  ASSERT_NE(at, r.keptFace.end());
  faces.erase(faces.begin() + (at - r.keptFace.begin()));
  EXPECT_EQ(faces, canonicalFaces(hole->surface));

  // The patch: the case's without face 851 and the one corner only that face uses.
  const MeshPtr patch = loaded("cases/bunny_small_back_removed_patch.obj");
  const Submesh expected =
      extractSubmesh(bunny->surface, std::vector<int>(r.removedFace.begin(), r.removedFace.end()));
  EXPECT_EQ(points(r.removed), points(expected.surface));
  EXPECT_EQ(canonicalFaces(r.removed), canonicalFaces(expected.surface));
  EXPECT_EQ(patch->surface.n_faces(), r.removed.n_faces() + 1);
  EXPECT_EQ(patch->surface.n_vertices(), r.removed.n_vertices() + 1);
}

// The same painting gives the same result, bit for bit.
TEST(CutRegion, IsDeterministic) {
  const MeshPtr armadillo = loaded("armadillo.obj");
  const Eigen::Vector3d centre = pointOf(armadillo->surface, 5000);
  const double radius = 0.05 * boundingDiagonal(armadillo->surface);
  const auto painted = paint(
      armadillo->surface, [&](const Eigen::Vector3d& p) { return (p - centre).norm() < radius; });
  const CutRegionResult a = cutPainted(armadillo->surface, painted);
  const CutRegionResult b = cutPainted(armadillo->surface, painted);
  EXPECT_TRUE(test::bitIdentical(a.mesh, b.mesh));
  EXPECT_TRUE(test::bitIdentical(a.removed, b.removed));
  EXPECT_EQ(a.border, b.border);
  expectManifoldPiece(a, 1, 1);
}

// Without a painting the loop nearest the point is picked and nothing changes.
TEST(CutRegion, NearPicksTheLoopClosestToThePoint) {
  const TriMesh grid = flatGrid(20);
  const auto left = paint(grid, [](const Eigen::Vector3d& p) {
    return (p - Eigen::Vector3d(-0.5, 0, 0)).norm() < 0.25;
  });
  const TriMesh once = cutPainted(grid, left).mesh;
  const auto right = paint(once, [](const Eigen::Vector3d& p) {
    return (p - Eigen::Vector3d(0.5, 0, 0)).norm() < 0.25;
  });
  const CutRegionResult holed = cutPainted(once, right);
  ASSERT_EQ(boundaryLoops(holed.mesh).size(), 3u);

  CutRegionOptions options;
  options.near = Eigen::Vector3d(0.45, 0.05, 0);
  const CutRegionResult picked = cutRegion(holed.mesh, options);
  EXPECT_EQ(picked.border, holed.border);
  EXPECT_TRUE(test::bitIdentical(picked.mesh, holed.mesh));
  EXPECT_EQ(picked.removed.n_faces(), 0u);
  options.near = Eigen::Vector3d(-0.55, 0.05, 0);
  const CutRegionResult other = cutRegion(holed.mesh, options);
  EXPECT_EQ(borderLoopProblem(holed.mesh, other.border), "");
  for (int b : other.border)
    EXPECT_LT(pointOf(holed.mesh, b).x(), 0);
  options.near = Eigen::Vector3d(2, 0, 0);  // nearer the grid's outer edge
  EXPECT_EQ(cutRegion(holed.mesh, options).border.size(), 80u);
}

TEST(CutRegion, NearPicksTheBunnyBackHole) {
  const MeshPtr hole = loaded("cases/bunny_small_back_hole.obj");
  CutRegionOptions options;
  options.near = Eigen::Vector3d(0.938688, 6.103354, 1.820958);
  const CutRegionResult r = cutRegion(hole->surface, options);
  EXPECT_EQ(r.border.size(), 18u);
  EXPECT_EQ(borderLoopProblem(hole->surface, r.border), "");
}

TEST(CutRegion, RefusesBadMeshesAndPaintings) {
  auto port = [](const TriMesh& mesh, const CutRegionOptions& options) -> std::string {
    try {
      cutRegion(mesh, options);
    } catch (const CutRegionError& e) {
      return e.port();
    }
    return "(accepted)";
  };
  const TriMesh grid = flatGrid(6);
  CutRegionOptions none;
  none.painted.assign(grid.n_vertices(), 0);
  EXPECT_EQ(port(grid, none), "strokes");
  CutRegionOptions all;
  all.painted.assign(grid.n_vertices(), 1);
  EXPECT_EQ(port(grid, all), "strokes");
  CutRegionOptions edge;  // touches the grid's own boundary
  edge.painted = paint(grid, [](const Eigen::Vector3d& p) { return p.x() < -0.9; });
  EXPECT_EQ(port(grid, edge), "strokes");
  CutRegionOptions nan;
  nan.near = Eigen::Vector3d(std::nan(""), 0, 0);
  EXPECT_EQ(port(grid, nan), "near");
  EXPECT_EQ(port(test::icosphere(2), CutRegionOptions{}), "mesh");  // closed: no hole to pick
  EXPECT_EQ(port(TriMesh(), CutRegionOptions{}), "mesh");

  TriMesh twoParts = grid;  // a second, separate triangle
  const auto a = twoParts.add_vertex({5, 0, 0}), b = twoParts.add_vertex({6, 0, 0}),
             c = twoParts.add_vertex({5, 1, 0});
  twoParts.add_face(a, b, c);
  EXPECT_EQ(port(twoParts, CutRegionOptions{}), "mesh");

  // A painting that reaches an existing hole would merge the two loops.
  const MeshPtr hole = loaded("cases/bunny_small_back_hole.obj");
  const auto loop = boundaryLoops(hole->surface).front();
  CutRegionOptions reaching;
  reaching.painted.assign(hole->surface.n_vertices(), 0);
  for (const auto w : hole->surface.vv_range(TriMesh::VertexHandle(loop[0])))
    if (!hole->surface.is_boundary(w)) reaching.painted[std::size_t(w.idx())] = 1;
  EXPECT_EQ(port(hole->surface, reaching), "strokes");
}

namespace {

// A canvas of the faces of `mesh` within `radius` of vertex `centre`, uv their projection on the
// plane through it across the vertex normal's direction: the painted disc stays on one side.
std::shared_ptr<Parameterization> localCanvas(const MeshPtr& mesh, int centre, double radius) {
  const TriMesh& m = mesh->surface;
  const Eigen::Vector3d o = pointOf(m, centre);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const auto f : m.vf_range(TriMesh::VertexHandle(centre))) {
    std::vector<Eigen::Vector3d> c;
    for (const auto v : m.fv_range(f))
      c.push_back(pointOf(m, v));
    normal += (c[1] - c[0]).cross(c[2] - c[0]);
  }
  normal.normalize();
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<int> faces;
  for (const auto f : m.faces())
    if (std::all_of(m.cfv_begin(f), m.cfv_end(f),
                    [&](auto w) { return (pointOf(m, w) - o).norm() < radius; }))
      faces.push_back(f.idx());
  Submesh sub = extractSubmesh(m, faces);
  auto canvas = std::make_shared<Canvas>();
  canvas->source = mesh;
  canvas->surface = sub.surface;
  canvas->sourceVertex = sub.sourceVertex;
  canvas->sourceFace = sub.sourceFace;
  auto param = std::make_shared<Parameterization>();
  for (int s : sub.sourceVertex) {
    const Eigen::Vector3d d = pointOf(m, s) - o;
    param->uv.emplace_back(d.dot(u), d.dot(v));
    param->normal.push_back(normal);
  }
  param->canvas = canvas;
  return param;
}

std::shared_ptr<Strokes> disc(double radius) {
  auto strokes = std::make_shared<Strokes>();
  strokes->dabs.push_back({Eigen::Vector2d::Zero(), radius, false});
  return strokes;
}

// The port a node run fails on, as the evaluator shows it.
std::string failingPort(std::map<std::string, ValuePtr, std::less<>> inputs,
                        const ParamMap& params = {}) {
  try {
    test::runNode("geobrush.cut_region", std::move(inputs), params);
  } catch (const NodeError& e) {
    return e.where();
  }
  return "(accepted)";
}

}  // namespace

// Through the node: painted on a canvas of the bunny, the region's faces go and the border lies
// on the output mesh; the report counts what went.
TEST(CutRegionNode, CutsThePaintedRegionOfACanvas) {
  const MeshPtr bunny = loaded("bunny_small.obj");
  const double diagonal = boundingDiagonal(bunny->surface);
  const auto run =
      test::runNode("geobrush.cut_region", {{"mesh", bunny},
                                            {"canvas", localCanvas(bunny, 100, 0.2 * diagonal)},
                                            {"strokes", disc(0.06 * diagonal)}});
  const auto mesh = run.get<Mesh>("mesh");
  const auto border = run.get<BorderLoop>("border");
  const auto removed = run.get<Mesh>("removed");
  const auto report = run.get<Metrics>("report");
  ASSERT_TRUE(mesh && border && removed && report);
  EXPECT_TRUE(run.warnings.empty());
  EXPECT_EQ(border->mesh, mesh);
  EXPECT_EQ(borderLoopProblem(mesh->surface, border->vertex), "");
  const test::Topology t = test::topology(mesh->surface);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.eulerCharacteristic, 1);
  EXPECT_GT(report->values.at("painted_vertices"), 5);
  EXPECT_EQ(report->values.at("removed_vertices"),
            double(bunny->surface.n_vertices() - mesh->surface.n_vertices()));
  EXPECT_EQ(report->values.at("removed_faces"), double(removed->surface.n_faces()));
  EXPECT_EQ(report->values.at("removed_faces") + double(mesh->surface.n_faces()),
            double(bunny->surface.n_faces()));
  EXPECT_EQ(report->values.at("border_vertices"), double(border->vertex.size()));
}

TEST(CutRegionNode, WithoutStrokesPicksAHoleAndRemovesNothing) {
  const MeshPtr hole = loaded("cases/bunny_small_back_hole.obj");
  const auto run = test::runNode("geobrush.cut_region", {{"mesh", hole}},
                                 {{"near", Vec3{0.938688, 6.103354, 1.820958}}});
  const auto border = run.get<BorderLoop>("border");
  ASSERT_TRUE(border);
  EXPECT_EQ(border->vertex.size(), 18u);
  EXPECT_TRUE(test::bitIdentical(run.get<Mesh>("mesh")->surface, hole->surface));
  EXPECT_EQ(run.get<Mesh>("removed")->surface.n_vertices(), 0u);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("removed_faces"), 0);
  EXPECT_EQ(run.get<Metrics>("report")->values.at("border_vertices"), 18);
}

// A painting wider than its canvas is cut where the canvas reaches, with a warning.
TEST(CutRegionNode, WarnsWhereThePaintingReachesTheCanvasBorder) {
  const MeshPtr bunny = loaded("bunny_small.obj");
  const double diagonal = boundingDiagonal(bunny->surface);
  auto param = localCanvas(bunny, 100, 0.1 * diagonal);
  auto canvas = std::make_shared<Canvas>(*param->canvas);
  setBoundaryAndOrigin(*canvas, 0, pointOf(canvas->surface, 0));
  param->canvas = canvas;
  const auto run = test::runNode("geobrush.cut_region",
                                 {{"mesh", bunny}, {"canvas", param}, {"strokes", disc(diagonal)}});
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings.front().find("canvas' border"), std::string::npos);
}

TEST(CutRegionNode, EachBadInputIsRefusedNamingItsPort) {
  const MeshPtr bunny = loaded("bunny_small.obj");
  const double diagonal = boundingDiagonal(bunny->surface);
  const auto canvas = localCanvas(bunny, 100, 0.2 * diagonal);
  EXPECT_EQ(failingPort({{"mesh", bunny}, {"strokes", disc(0.05 * diagonal)}}), "input 'canvas'");
  EXPECT_EQ(failingPort({{"mesh", bunny}, {"canvas", canvas}}), "input 'strokes'");
  // Strokes painting away from the canvas.
  auto away = std::make_shared<Strokes>();
  away->dabs.push_back({Eigen::Vector2d(100 * diagonal, 0), 0.01, false});
  EXPECT_EQ(failingPort({{"mesh", bunny}, {"canvas", canvas}, {"strokes", away}}),
            "input 'strokes'");
  // A canvas of another mesh.
  const MeshPtr sphere = primitive("sphere", 8);
  EXPECT_EQ(failingPort({{"mesh", sphere}, {"canvas", canvas}, {"strokes", disc(0.1)}}),
            "input 'canvas'");
  // A canvas whose arrays disagree.
  auto shortUv = std::make_shared<Parameterization>(*canvas);
  shortUv->uv.pop_back();
  EXPECT_EQ(failingPort({{"mesh", bunny}, {"canvas", shortUv}, {"strokes", disc(0.1)}}),
            "input 'canvas'");
  // A closed mesh has no hole to pick.
  EXPECT_EQ(failingPort({{"mesh", sphere}}), "input 'mesh'");
  // Painting the whole canvas of a small closed mesh leaves nothing.
  const auto all = localCanvas(sphere, 0, 10);
  EXPECT_EQ(failingPort({{"mesh", sphere}, {"canvas", all}, {"strokes", disc(100)}}),
            "input 'strokes'");
}

// The real pipeline: the target DEM of bunny_small (keep_holes) maps the shared domain onto the
// mesh, the strokes paint a disc in it, and the cut opens one loop in one manifold piece.
TEST(CutRegionNode, CutsADiscPaintedThroughTheTargetDem) {
  Graph graph;
  graph.file = test::tempDir("cut_region_dem") / "graph.json";
  graph.nodes["source_mesh"] = {
      "geobrush.primitive", 1, {{"shape", std::string("plane")}, {"resolution", std::int64_t(24)}}};
  graph.nodes["source_canvas"] = {
      "geobrush.canvas_grow", 1, {{"dabs", std::vector<double>{0.0, 0.0, 0.0, 2.0}}}};
  graph.nodes["source_map"] = {"geobrush.gdem", 1, {}};
  graph.nodes["target_mesh"] = {
      "geobrush.load_mesh", 1, {{"path", test::meshPath("bunny_small.obj").string()}}};
  graph.nodes["target_map"] = {
      "geobrush.dem",
      1,
      {{"origin", Vec3{0.938688, 6.103354, 1.820958}}, {"scale", 4.0}, {"keep_holes", true}}};
  graph.nodes["strokes"] = {
      "geobrush.strokes", 1, {{"dabs", std::vector<double>{0.0, 0.0, 0.25, 1.0}}}};
  graph.nodes["cut"] = {"geobrush.cut_region", 1, {}};
  graph.connections = {{{"source_mesh", "mesh"}, {"source_canvas", "mesh"}},
                       {{"source_canvas", "canvas"}, {"source_map", "canvas"}},
                       {{"target_mesh", "mesh"}, {"target_map", "mesh"}},
                       {{"source_map", "parameterization"}, {"target_map", "source"}},
                       {{"target_mesh", "mesh"}, {"cut", "mesh"}},
                       {{"target_map", "parameterization"}, {"cut", "canvas"}},
                       {{"strokes", "strokes"}, {"cut", "strokes"}}};
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  const auto mesh = std::dynamic_pointer_cast<const Mesh>(evaluator.output("cut", "mesh"));
  const auto border =
      std::dynamic_pointer_cast<const BorderLoop>(evaluator.output("cut", "border"));
  const auto metrics = std::dynamic_pointer_cast<const Metrics>(evaluator.output("cut", "report"));
  ASSERT_TRUE(mesh && border && metrics);
  const test::Topology t = test::topology(mesh->surface);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.eulerCharacteristic, 1);
  EXPECT_EQ(borderLoopProblem(mesh->surface, border->vertex), "");
  EXPECT_GT(metrics->values.at("removed_vertices"), 5);
  // Vertex 100, the DEM's origin, is painted: its point is gone from the result.
  const Eigen::Vector3d origin(0.938688, 6.103354, 1.820958);
  for (const auto v : mesh->surface.vertices())
    EXPECT_GT((pointOf(mesh->surface, v) - origin).norm(), 1e-3);
}

}  // namespace geobrush
