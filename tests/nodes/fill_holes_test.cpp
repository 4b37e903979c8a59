#include "fill_holes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "hole_membrane.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Deletes the faces `remove` picks (by their centroid) and the vertices left without a face.
TriMesh withoutFaces(TriMesh mesh, const std::function<bool(const Vector3d&)>& remove) {
  for (auto f : mesh.faces()) {
    Vector3d centroid = Vector3d::Zero();
    for (auto v : mesh.fv_range(f))
      centroid += pointOf(mesh, v.idx()) / 3.0;
    if (remove(centroid)) mesh.delete_face(f, true);
  }
  mesh.garbage_collection();
  return mesh;
}

std::vector<Vector3d> newPoints(const TriMesh& filled, const TriMesh& holed) {
  std::vector<Vector3d> points;
  for (int v = int(holed.n_vertices()); v < int(filled.n_vertices()); ++v)
    points.push_back(pointOf(filled, v));
  return points;
}

// The input's vertices and faces, unchanged and in their order, begin the output.
void expectInputKept(const TriMesh& input, const TriMesh& output) {
  ASSERT_GE(output.n_vertices(), input.n_vertices());
  ASSERT_GE(output.n_faces(), input.n_faces());
  for (auto v : input.vertices())
    ASSERT_EQ(input.point(v), output.point(v)) << v.idx();
  for (auto f : input.faces()) {
    std::vector<int> a, b;
    for (auto v : input.fv_range(f))
      a.push_back(v.idx());
    for (auto v : output.fv_range(TriMesh::FaceHandle(f.idx())))
      b.push_back(v.idx());
    ASSERT_EQ(a, b) << f.idx();
  }
}

FillHolesOptions listed(std::vector<int> loops, int continuity = 1) {
  FillHolesOptions options;
  options.selection = HoleSelection::Listed;
  options.loops = std::move(loops);
  options.continuity = continuity;
  return options;
}

// Face pairs that meet beyond a shared vertex (core's test, to rounding; the exact count is in
// tests/reference).
std::size_t intersectingPairs(const TriMesh& mesh) {
  std::vector<int> faces(mesh.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  return selfIntersections(mesh, faces, 1e-12 * boundingDiagonal(mesh));
}

TEST(FillHoles, FindsEachLoopStartingAtItsSmallestVertex) {
  const TriMesh holed = withoutFaces(test::unitSquareGrid(20), [](const Vector3d& c) {
    return (c - Vector3d(0.3, 0.3, 0)).norm() < 0.1 || (c - Vector3d(0.7, 0.7, 0)).norm() < 0.12;
  });
  const auto loops = boundaryLoops(holed);
  ASSERT_EQ(loops.size(), 3u);
  EXPECT_EQ(loops[0].vertices.front(), 0);  // the square's own border
  EXPECT_NEAR(loops[0].length, 4.0, 1e-12);
  for (const auto& loop : loops) {
    EXPECT_EQ(*std::min_element(loop.vertices.begin(), loop.vertices.end()), loop.vertices.front());
    for (std::size_t i = 0; i < loop.vertices.size(); ++i) {
      const auto h =
          holed.find_halfedge(TriMesh::VertexHandle(loop.vertices[i]),
                              TriMesh::VertexHandle(loop.vertices[(i + 1) % loop.vertices.size()]));
      ASSERT_TRUE(h.is_valid());
      EXPECT_TRUE(holed.is_boundary(h));
    }
  }
  EXPECT_LT(loops[1].vertices.front(), loops[2].vertices.front());
}

TEST(FillHoles, APlanarHoleFillsFlatWithEdgesLikeItsBorder) {
  const TriMesh holed = withoutFaces(test::unitSquareGrid(30), [](const Vector3d& c) {
    return (c - Vector3d(0.5, 0.5, 0)).norm() < 0.25;
  });
  const auto result = fillHoles(holed, listed({1}));
  expectInputKept(holed, result.mesh);
  const auto topo = test::topology(result.mesh);
  EXPECT_EQ(topo.boundaryLoops, 1u);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(topo.components, 1u);
  for (const auto& p : newPoints(result.mesh, holed))
    EXPECT_NEAR(p.z(), 0.0, 1e-12);
  for (int f = int(holed.n_faces()); f < int(result.mesh.n_faces()); ++f) {
    const auto n = result.mesh.calc_face_normal(TriMesh::FaceHandle(f));
    EXPECT_GT(n[2], 0.999) << f;  // facing as the mesh around it
  }
  const auto& hole = result.holes[1];
  EXPECT_TRUE(hole.filled);
  EXPECT_GT(hole.newVertices, 0);
  EXPECT_GE(hole.newMeanEdge, 0.7 * hole.borderMeanEdge);
  EXPECT_LE(hole.newMeanEdge, 1.5 * hole.borderMeanEdge);
  EXPECT_GT(test::minAngleDegrees(result.mesh), 20.0);
  EXPECT_FALSE(result.holes[0].filled);
  EXPECT_EQ(result.holes[0].leftOpen, "not chosen");
}

TEST(FillHoles, ALongSlotFillsFlat) {
  const TriMesh holed = withoutFaces(test::unitSquareGrid(40), [](const Vector3d& c) {
    return std::abs(c.x() - 0.5) < 0.4 && std::abs(c.y() - 0.5) < 0.03;
  });
  const auto result = fillHoles(holed, listed({1}));
  EXPECT_EQ(test::topology(result.mesh).boundaryLoops, 1u);
  for (const auto& p : newPoints(result.mesh, holed))
    EXPECT_NEAR(p.z(), 0.0, 1e-12);
  for (int f = int(holed.n_faces()); f < int(result.mesh.n_faces()); ++f)
    EXPECT_GT(result.mesh.calc_face_normal(TriMesh::FaceHandle(f))[2], 0.999) << f;
  EXPECT_EQ(intersectingPairs(result.mesh), 0u);
}

// Heights of a sphere over the plane tangent at its pole: biharmonic fills take its curvature
// from the border's slopes; harmonic ones flatten it.
TEST(FillHoles, ASphereCapComesBackOnTheSphereAndC1BeatsC0) {
  const TriMesh sphere = test::icosphere(5);
  const TriMesh holed = withoutFaces(sphere, [](const Vector3d& c) { return c.z() > 0.9; });
  double error[2] = {0, 0};
  for (int continuity : {0, 1}) {
    const auto result = fillHoles(holed, listed({0}, continuity));
    expectInputKept(holed, result.mesh);
    EXPECT_EQ(test::topology(result.mesh).boundaryLoops, 0u);
    for (const auto& p : newPoints(result.mesh, holed))
      error[continuity] = std::max(error[continuity], std::abs(p.norm() - 1.0));
  }
  // The cap rises 0.1 above its border: the C0 fill stays near the border's plane.
  EXPECT_GT(error[0], 0.05);
  EXPECT_LT(error[1], 0.004);
}

TEST(FillHoles, MembraneReproducesAPlaneFromItsRing) {
  // A triangulated hexagon ring around three unknowns, all heights on the plane h = 2u - v + 1.
  const TriMesh grid = test::unitSquareGrid(6);
  const TriMesh holed = withoutFaces(
      grid, [](const Vector3d& c) { return (c - Vector3d(0.5, 0.5, 0)).norm() < 0.2; });
  TriMesh tilted = holed;
  for (auto v : tilted.vertices()) {
    auto p = tilted.point(v);
    p[2] = 2 * p[0] - p[1] + 1;
    tilted.set_point(v, p);
  }
  const auto result = fillHoles(tilted, listed({1}));
  for (const auto& p : newPoints(result.mesh, tilted))
    EXPECT_NEAR(p.z(), 2 * p.x() - p.y() + 1, 1e-10);
}

// A strip wound one and a half times around an axis: its one border loop overlaps itself
// seen from any side, so it is no disc in a plane; over its smoothed chart the fill spans it
// like a spiral staircase, closing the strip into one sheet without cutting it.
TEST(FillHoles, ALoopThatOverlapsItselfInEveryPlaneFillsWithoutCuttingTheSurface) {
  TriMesh strip;
  const int n = 90;
  for (int i = 0; i <= n; ++i) {
    const double angle = 3.0 * M_PI * i / n;
    for (double w : {0.0, 0.3})
      strip.add_vertex(TriMesh::Point(std::cos(angle), std::sin(angle), 0.1 * angle + w));
  }
  for (int i = 0; i < n; ++i) {
    const TriMesh::VertexHandle a(2 * i), b(2 * i + 1), c(2 * i + 2), d(2 * i + 3);
    strip.add_face(a, c, d);
    strip.add_face(a, d, b);
  }
  EXPECT_FALSE(chartHole(strip, boundaryLoops(strip)[0]).planar);
  const auto result = fillHoles(strip, {});
  expectInputKept(strip, result.mesh);
  EXPECT_EQ(test::topology(result.mesh).boundaryLoops, 0u);
  EXPECT_EQ(test::topology(result.mesh).nonManifoldVertices, 0u);
  EXPECT_EQ(intersectingPairs(result.mesh), 0u);
}

// Appends a closed tetrahedron (a pin) to `mesh`.
void addPin(TriMesh& mesh, const std::array<OpenMesh::Vec3d, 4>& corners) {
  const Mesh pin = test::tetrahedron(corners);
  std::vector<TriMesh::VertexHandle> added;
  for (auto v : pin.surface.vertices())
    added.push_back(mesh.add_vertex(pin.surface.point(v)));
  for (auto f : pin.surface.faces()) {
    std::vector<TriMesh::VertexHandle> face;
    for (auto v : pin.surface.fv_range(f))
      face.push_back(added[std::size_t(v.idx())]);
    mesh.add_face(face);
  }
}

// A hole at the top of a mound, under a pin that stops short of the hole's plane: the C1 fill
// rises with the mound's slopes into the pin, the harmonic one stays below it.
TEST(FillHoles, AFillTheSlopesWouldFoldIntoTheSurfaceIsFilledHarmonic) {
  TriMesh mesh = withoutFaces(test::unitSquareGrid(20), [](const Vector3d& c) {
    return (c - Vector3d(0.5, 0.5, 0)).norm() < 0.25;
  });
  for (auto v : mesh.vertices()) {
    auto p = mesh.point(v);
    p[2] = -0.5 * std::max(0.0, std::hypot(p[0] - 0.5, p[1] - 0.5) - 0.25);
    mesh.set_point(v, p);
  }
  addPin(mesh,
         {OpenMesh::Vec3d(0.4, 0.4, 0.03), {0.6, 0.4, 0.03}, {0.5, 0.6, 0.03}, {0.5, 0.5, 0.5}});
  const auto c1 = fillHoles(mesh, listed({1}));
  EXPECT_EQ(c1.holes[1].continuity, 0);
  EXPECT_TRUE(test::contains(c1.holes[1].note, "filled harmonic"));
  EXPECT_EQ(intersectingPairs(c1.mesh), 0u);
  const auto c0 = fillHoles(mesh, listed({1}, 0));
  for (auto v : c0.mesh.vertices())
    ASSERT_EQ(c0.mesh.point(v), c1.mesh.point(v));
}

// A pin through a hole: any disc spanning the hole cuts it, so the fill fails, naming the loop.
TEST(FillHoles, AFillThatWouldCutTheSurfaceFailsNamingItsLoop) {
  TriMesh mesh = withoutFaces(test::unitSquareGrid(10), [](const Vector3d& c) {
    return (c - Vector3d(0.5, 0.5, 0)).norm() < 0.25;
  });
  const Mesh pin = test::tetrahedron(
      {OpenMesh::Vec3d(0.45, 0.45, -0.5), {0.55, 0.45, -0.5}, {0.5, 0.55, -0.5}, {0.5, 0.5, 0.5}});
  std::vector<TriMesh::VertexHandle> corners;
  for (auto v : pin.surface.vertices())
    corners.push_back(mesh.add_vertex(pin.surface.point(v)));
  for (auto f : pin.surface.faces()) {
    std::vector<TriMesh::VertexHandle> face;
    for (auto v : pin.surface.fv_range(f))
      face.push_back(corners[std::size_t(v.idx())]);
    mesh.add_face(face);
  }
  try {
    fillHoles(mesh, listed({1}));
    FAIL() << "the hole was filled through the pin";
  } catch (const FillHolesError& e) {
    EXPECT_EQ(e.loop(), 1);
    EXPECT_TRUE(test::contains(e.what(), "loop 1 ("));
    EXPECT_TRUE(test::contains(e.what(), "its fill would cut through the surface"));
  }
}

// A square hole whose diagonal the mesh already has (a face bridging over it): the chord of the
// fill along it is split at its midpoint, on both sides.
TEST(FillHoles, AChordTheMeshAlreadyHasIsSplit) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (const auto& p : {TriMesh::Point(0, 0, 0), TriMesh::Point(1, 0, 0), TriMesh::Point(1, 1, 0),
                        TriMesh::Point(0, 1, 0), TriMesh::Point(0.5, 0.5, 1)})
    v.push_back(mesh.add_vertex(p));
  mesh.add_face(v[0], v[2], v[4]);  // a bridge whose edge 0-2 spans the square
  BoundaryLoop loop;
  loop.vertices = {0, 1, 2, 3};
  PlanarPatch patch;
  patch.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  patch.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  std::vector<double> size(4, 1.0);
  splitExistingChords(patch, mesh, loop, size);
  ASSERT_EQ(patch.points.size(), 5u);
  EXPECT_EQ(patch.points[4], Vector2d(0.5, 0.5));
  EXPECT_EQ(size.size(), 5u);
  ASSERT_EQ(patch.triangles.size(), 4u);
  for (const auto& t : patch.triangles) {
    EXPECT_NE(std::find(t.begin(), t.end(), 4), t.end());  // every triangle meets the midpoint
    const Vector2d &a = patch.points[std::size_t(t[0])], &b = patch.points[std::size_t(t[1])],
                   &c = patch.points[std::size_t(t[2])];
    EXPECT_GT((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(), 0.0);  // still CCW
  }
}

TEST(FillHoles, TheChoiceLeavesTheLargestTheUnlistedOrTheLongLoopsOpen) {
  const TriMesh holed = withoutFaces(test::unitSquareGrid(20), [](const Vector3d& c) {
    return (c - Vector3d(0.3, 0.3, 0)).norm() < 0.1 || (c - Vector3d(0.7, 0.7, 0)).norm() < 0.2;
  });
  FillHolesOptions butLargest;
  butLargest.selection = HoleSelection::AllButLargest;
  auto result = fillHoles(holed, butLargest);
  EXPECT_EQ(result.holes[0].leftOpen, "the largest loop");
  EXPECT_TRUE(result.holes[1].filled && result.holes[2].filled);
  EXPECT_EQ(test::topology(result.mesh).boundaryLoops, 1u);

  butLargest.maxBorderEdges = result.holes[1].borderEdges;
  result = fillHoles(holed, butLargest);
  EXPECT_TRUE(result.holes[1].filled);
  EXPECT_FALSE(result.holes[2].filled);
  EXPECT_TRUE(test::contains(result.holes[2].leftOpen, "border edges"));

  EXPECT_THROW(fillHoles(holed, listed({3})), std::invalid_argument);
  FillHolesOptions bad;
  bad.continuity = 2;
  EXPECT_THROW(fillHoles(holed, bad), std::invalid_argument);
}

TEST(FillHoles, TheSameMeshFillsBitForBitTheSame) {
  const auto holed = readMesh(test::meshPath("bunny_scan.obj")).mesh->surface;
  const auto a = fillHoles(holed, {}), b = fillHoles(holed, {});
  ASSERT_EQ(a.mesh.n_vertices(), b.mesh.n_vertices());
  for (auto v : a.mesh.vertices())
    ASSERT_EQ(a.mesh.point(v), b.mesh.point(v));
}

void expectCleanClosedFill(const TriMesh& holed, const FillHolesResult& result) {
  expectInputKept(holed, result.mesh);
  const auto topo = test::topology(result.mesh);
  EXPECT_EQ(topo.boundaryLoops, 0u);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(intersectingPairs(result.mesh), 0u);
  for (const auto& hole : result.holes) {
    EXPECT_TRUE(hole.filled) << hole.loop;
    EXPECT_GE(hole.newMeanEdge, 0.7 * hole.borderMeanEdge) << hole.loop;
    EXPECT_LE(hole.newMeanEdge, 1.5 * hole.borderMeanEdge) << hole.loop;
  }
}

TEST(FillHoles, TheScannedBunnysFiveHolesCloseCleanly) {
  const auto holed = readMesh(test::meshPath("bunny_scan.obj")).mesh->surface;
  const auto result = fillHoles(holed, {});
  ASSERT_EQ(result.holes.size(), 5u);
  expectCleanClosedFill(holed, result);
}

// Loop 0 runs in a zigzag along a chamfer, folding in projection: its chart is the projection
// smoothed along the loop. Loop 1 lies in a plane.
TEST(FillHoles, TheHolesOfACadPartCloseAndItsPlanarHoleFillsPlanar) {
  const auto holed = readMesh(test::meshPath("mech_holes_shark.obj")).mesh->surface;
  const auto result = fillHoles(holed, {});
  ASSERT_EQ(result.holes.size(), 4u);
  expectCleanClosedFill(holed, result);
  EXPECT_FALSE(chartHole(holed, boundaryLoops(holed)[0]).planar);
  // A loop whose border lies in a plane fills in that plane (its chart's plane, height 0).
  const auto loops = boundaryLoops(holed);
  const double diag = boundingDiagonal(holed);
  int planarLoops = 0;
  std::size_t next = holed.n_vertices();
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const HoleChart chart = chartHole(holed, loops[i]);
    double border = 0.0;
    for (int v : loops[i].vertices)
      border = std::max(border, std::abs(chart.height(pointOf(holed, v))));
    const bool planar = chart.planar && border <= 1e-6 * diag;
    planarLoops += planar;
    for (int k = 0; k < result.holes[i].newVertices; ++k, ++next) {
      if (planar) {
        EXPECT_LE(std::abs(chart.height(pointOf(result.mesh, int(next)))), 1e-6 * diag);
      }
    }
  }
  EXPECT_EQ(planarLoops, 1);
}

// The cut holes (their distance to the removed patches is in tests/reference, against CGAL's).
class CutHole : public ::testing::TestWithParam<const char*> {};

TEST_P(CutHole, FillsCleanly) {
  const std::string name = GetParam();
  const auto holed = readMesh(test::meshDir() / "cases" / (name + "_hole.obj")).mesh->surface;
  expectCleanClosedFill(holed, fillHoles(holed, {}));
}

INSTANTIATE_TEST_SUITE_P(Cases, CutHole,
                         ::testing::Values("bunny_small_back", "nefertiti_forehead",
                                           "nefertiti_back"));

TEST(FillHolesNode, ReportsEachLoopAndNamesABadChoice) {
  const NodeType* type = test::registry().find("geobrush.fill_holes");
  ASSERT_NE(type, nullptr);
  const TriMesh holed = withoutFaces(test::unitSquareGrid(20), [](const Vector3d& c) {
    return (c - Vector3d(0.5, 0.5, 0)).norm() < 0.2;
  });
  auto input = std::make_shared<const Mesh>(holed);
  test::DirectContext ctx(*type, {{"mesh", input}}, {{"holes", std::string("all-but-largest")}});
  type->create()->compute(ctx);
  const auto out = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["mesh"]);
  const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
  ASSERT_TRUE(out && report);
  EXPECT_EQ(test::topology(out->surface).boundaryLoops, 1u);
  EXPECT_EQ(report->values.at("loops"), 2.0);
  EXPECT_EQ(report->values.at("filled"), 1.0);
  EXPECT_EQ(report->values.at("loop.0.filled"), 0.0);
  EXPECT_EQ(report->values.at("loop.1.new_vertices"), report->values.at("new_vertices"));
  EXPECT_GT(report->values.at("loop.1.border_edges"), 0.0);
  ASSERT_EQ(report->notes.size(), 1u);
  EXPECT_TRUE(test::contains(report->notes[0], "loop 0 left open: the largest loop"));
  // The map: the input's vertices kept, the fill's new, the new faces at the border the seam.
  const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs["map"]);
  ASSERT_TRUE(map);
  ASSERT_EQ(map->targetVertex.size(), out->surface.n_vertices());
  for (std::size_t v = 0; v < out->surface.n_vertices(); ++v)
    EXPECT_EQ(map->targetVertex[v], v < holed.n_vertices() ? int(v) : -1);
  EXPECT_EQ(double(out->surface.n_vertices() - holed.n_vertices()),
            report->values.at("new_vertices"));
  EXPECT_FALSE(map->seamFaces.empty());
  for (int f : map->seamFaces)
    EXPECT_GE(f, int(holed.n_faces()));

  for (const std::string bad : {"", "1,", "x", "-1"}) {
    test::DirectContext badCtx(*type, {{"mesh", input}}, {{"holes", bad}});
    try {
      type->create()->compute(badCtx);
      ADD_FAILURE() << "accepted holes=" << bad;
    } catch (const NodeError& e) {
      EXPECT_TRUE(test::contains(e.what(), "loop ids like 0,2")) << e.what();
    }
  }
  test::DirectContext missing(*type, {{"mesh", input}}, {{"holes", std::string("5")}});
  EXPECT_THROW(type->create()->compute(missing), NodeError);
}

}  // namespace
}  // namespace geobrush
