#include "weld.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

Vector3d centroid(const TriMesh& mesh, TriMesh::FaceHandle f) {
  Vector3d sum = Vector3d::Zero();
  for (auto v : mesh.fv_range(f))
    sum += pointOf(mesh, v) / 3.0;
  return sum;
}

// The mesh cut in two by the faces whose centroid `inside` picks: the holed rest (vertices and
// faces in their order) and the removed patch.
struct Cut {
  TriMesh holed, patch;
};
Cut cut(const TriMesh& mesh, const std::function<bool(const Vector3d&)>& inside) {
  Cut result;
  result.holed = mesh;
  std::vector<int> removed;
  for (auto f : mesh.faces())
    if (inside(centroid(mesh, f))) {
      removed.push_back(f.idx());
      result.holed.delete_face(TriMesh::FaceHandle(f.idx()), true);
    }
  result.holed.garbage_collection();
  appendFaces(result.patch, mesh, removed);
  return result;
}

bool inCentreSquare(const Vector3d& c) {
  return std::abs(c.x() - 0.5) < 0.2 && std::abs(c.y() - 0.5) < 0.2;
}

// The grid's hole: the boundary loop without the grid's corner vertex 0.
std::vector<int> holeLoop(const TriMesh& holed) {
  const auto loops = boundaryLoops(holed);
  EXPECT_EQ(loops.size(), 2u);
  return loops.back();
}

TriMesh flipped(const TriMesh& mesh) {
  TriMesh out;
  for (auto v : mesh.vertices())
    out.add_vertex(mesh.point(v));
  for (auto f : mesh.faces()) {
    std::vector<TriMesh::VertexHandle> c;
    for (auto v : mesh.fv_range(f))
      c.push_back(v);
    out.add_face(c[0], c[2], c[1]);
  }
  return out;
}

// Every point moved toward `centre` by `share` of its distance (the points `move` picks).
TriMesh shrunk(
    TriMesh mesh, const Vector3d& centre, double share,
    const std::function<bool(int)>& move = [](int) { return true; }) {
  for (auto v : mesh.vertices()) {
    if (!move(v.idx())) continue;
    const Vector3d p = pointOf(mesh, v);
    const Vector3d q = p + share * (centre - p);
    mesh.set_point(v, {q.x(), q.y(), q.z()});
  }
  return mesh;
}

// The faces as point triples, each starting at its smallest point: equal for meshes whose
// vertices are numbered differently.
std::vector<std::array<std::array<double, 3>, 3>> faceSet(const TriMesh& mesh) {
  std::vector<std::array<std::array<double, 3>, 3>> faces;
  for (auto f : mesh.faces()) {
    std::array<std::array<double, 3>, 3> t;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto& p = mesh.point(v);
      t[std::size_t(k++)] = {p[0], p[1], p[2]};
    }
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    faces.push_back(t);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

void expectManifoldWithLoops(const TriMesh& mesh, std::size_t loops, long euler) {
  const auto topo = test::topology(mesh);
  EXPECT_EQ(topo.boundaryLoops, loops);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(topo.components, 1u);
  EXPECT_EQ(topo.isolatedVertices, 0u);
  EXPECT_EQ(topo.eulerCharacteristic, euler);
}

// Faces from `first` on face +z with some area.
void expectFacingUp(const TriMesh& mesh, int first) {
  for (int f = first; f < int(mesh.n_faces()); ++f) {
    const auto fh = TriMesh::FaceHandle(f);
    const auto it = mesh.cfv_begin(fh);
    const Vector3d a = pointOf(mesh, *it), b = pointOf(mesh, *std::next(it)),
                   c = pointOf(mesh, *std::next(it, 2));
    const Vector3d n = (b - a).cross(c - a);
    EXPECT_GT(n.z(), 1e-6) << "face " << f;
  }
}

TEST(Weld, AnExactPatchClosesTheGridAsIfNeverCut) {
  const TriMesh grid = test::unitSquareGrid(10);
  const Cut c = cut(grid, inCentreSquare);
  ASSERT_EQ(c.patch.n_faces(), 32u);
  const auto result = weld(c.holed, holeLoop(c.holed), c.patch);
  EXPECT_EQ(result.sharedVertices, 16u);
  EXPECT_EQ(result.stripFaces, 0u);
  EXPECT_FALSE(result.patchFlipped);
  EXPECT_EQ(result.trimmedFaces, 0u);
  const auto topo = test::topology(result.mesh), uncut = test::topology(grid);
  EXPECT_EQ(topo.vertices, uncut.vertices);
  EXPECT_EQ(topo.edges, uncut.edges);
  EXPECT_EQ(topo.faces, uncut.faces);
  expectManifoldWithLoops(result.mesh, 1, uncut.eulerCharacteristic);
  EXPECT_EQ(faceSet(result.mesh), faceSet(grid));
  // The holed mesh comes first, unchanged; the map tells the two sides apart.
  for (auto v : c.holed.vertices()) {
    EXPECT_EQ(result.mesh.point(v), c.holed.point(v));
    EXPECT_EQ(result.map.targetVertex[std::size_t(v.idx())], v.idx());
  }
  for (std::size_t v = c.holed.n_vertices(); v < result.mesh.n_vertices(); ++v) {
    EXPECT_EQ(result.map.targetVertex[v], -1);
    EXPECT_GE(result.map.sourceVertex[v], 0);
  }
  std::size_t sharedInMap = 0;
  for (std::size_t v = 0; v < c.holed.n_vertices(); ++v)
    sharedInMap += result.map.sourceVertex[v] >= 0;
  EXPECT_EQ(sharedInMap, 16u);
  // The seam is the patch faces on the hole's 16 edges (two in each of two corners).
  EXPECT_EQ(result.map.seamFaces.size(), 14u);
  for (int f : result.map.seamFaces)
    EXPECT_GE(f, int(c.holed.n_faces()));
}

// A patch twice as fine as the hole: every other boundary vertex lies on a border vertex, the
// rest on the middles of the border's edges, which are split there and shared: no strip at all.
TEST(Weld, APatchFinerThanTheHoleSplitsTheBordersEdges) {
  const TriMesh grid = test::unitSquareGrid(10);
  const Cut c = cut(grid, inCentreSquare);
  TriMesh finer = test::unitSquareGrid(8);
  for (auto v : finer.vertices())
    finer.set_point(v, finer.point(v) * 0.4 + TriMesh::Point(0.3, 0.3, 0));
  const auto result = weld(c.holed, holeLoop(c.holed), finer);
  EXPECT_EQ(result.sharedVertices, 32u);
  EXPECT_EQ(result.borderSplits, 16u);
  EXPECT_EQ(result.stripFaces, 0u);
  EXPECT_EQ(result.trimmedFaces, 0u);
  expectManifoldWithLoops(result.mesh, 1, test::topology(grid).eulerCharacteristic);
  EXPECT_NEAR(test::surfaceArea(result.mesh), 1.0, 1e-12);
  expectFacingUp(result.mesh, 0);
  for (auto v : c.holed.vertices())
    EXPECT_EQ(result.mesh.point(v), c.holed.point(v));
  for (std::size_t v = c.holed.n_vertices(); v < c.holed.n_vertices() + 16; ++v)
    EXPECT_EQ(result.map.targetVertex[v], -1);  // the split points belong to neither input
}

// A 2 x 2 block of cells cut from the grid but one face: an ear of the holed mesh, with two border
// edges and its tip at the block's centre (0.5, 0.5).
Cut earHole(const TriMesh& grid) {
  const Vector3d earCentroid(0.4 + 0.2 / 3, 0.4 + 0.1 / 3, 0);
  return cut(grid, [&](const Vector3d& p) {
    return std::abs(p.x() - 0.5) < 0.1 && std::abs(p.y() - 0.5) < 0.1 &&
           (p - earCentroid).norm() > 1e-9;
  });
}

// The block's rim fanned from `hub`: its edge from (0.4, 0.4) to (0.5, 0.4) joins the ear's two
// neighbours behind the ear.
TriMesh rimFan(const Vector3d& hub) {
  TriMesh patch;
  std::vector<TriMesh::VertexHandle> rim;
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.4, 0.4},
                                                                   {0.5, 0.4},
                                                                   {0.6, 0.4},
                                                                   {0.6, 0.5},
                                                                   {0.6, 0.6},
                                                                   {0.5, 0.6},
                                                                   {0.4, 0.6},
                                                                   {0.4, 0.5}})
    rim.push_back(patch.add_vertex({x, y, 0}));
  const auto centre = patch.add_vertex(toPoint(hub));
  for (std::size_t k = 0; k < rim.size(); ++k)
    patch.add_face(rim[k], rim[(k + 1) % rim.size()], centre);
  return patch;
}

// The patch face behind the ear would overlap it: its edge is split at the ear's tip and the patch
// runs around the ear.
TEST(Weld, APatchEdgeBehindAnEarOfTheHoleIsSplitAtTheEarsTip) {
  const TriMesh grid = test::unitSquareGrid(10);
  const Cut c = earHole(grid);
  ASSERT_EQ(c.patch.n_faces(), 7u);
  const TriMesh patch = rimFan({0.54, 0.56, 0});
  const auto result = weld(c.holed, holeLoop(c.holed), patch);
  EXPECT_EQ(result.earSplits, 1u);
  EXPECT_EQ(result.sharedVertices, 9u);  // the rim and the tip
  EXPECT_EQ(result.stripFaces, 0u);
  EXPECT_EQ(result.trimmedFaces, 0u);
  EXPECT_EQ(result.mesh.n_faces(), c.holed.n_faces() + patch.n_faces() + 1);
  expectManifoldWithLoops(result.mesh, 1, test::topology(grid).eulerCharacteristic);
  EXPECT_NEAR(test::surfaceArea(result.mesh), 1.0, 1e-12);  // nothing overlaps
  expectFacingUp(result.mesh, 0);
  for (auto v : c.holed.vertices())
    EXPECT_EQ(result.mesh.point(v), c.holed.point(v));
  // The tip is the holed mesh's vertex; no vertex of the patch stands for it.
  EXPECT_EQ(result.mesh.n_vertices(), c.holed.n_vertices() + 1);  // the hub
  std::size_t fromPatch = 0;
  for (int s : result.map.sourceVertex)
    fromPatch += s >= 0;
  EXPECT_EQ(fromPatch, patch.n_vertices());
}

// A hub west of the tip would turn the half of the face east of the tip over, and with the faces
// over the ear removed the hub is too far from the tip to take its place: the gap left runs
// through the tip, and the weld refuses rather than fold the seam.
TEST(Weld, AnEarThePatchFaceCannotRunAroundIsRefused) {
  const Cut c = earHole(test::unitSquareGrid(10));
  try {
    weld(c.holed, holeLoop(c.holed), rimFan({0.45, 0.55, 0}));
    ADD_FAILURE() << "welded a patch that overlaps the ear";
  } catch (const WeldError& e) {
    EXPECT_EQ(e.port(), "patch");
    EXPECT_NE(std::string(e.what()).find("pairs of faces intersect"), std::string::npos)
        << e.what();
  }
}

// The ear's 2 x 2 block triangulated along the other diagonals, its centre a little off the tip:
// the faces of the cell holding the ear overlap it, and no edge split can run around it.
TriMesh otherDiagonalBlock(const Vector3d& centre) {
  TriMesh block;
  std::vector<TriMesh::VertexHandle> v;
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i)
      v.push_back(block.add_vertex({0.4 + 0.1 * i, 0.4 + 0.1 * j, 0}));
  block.set_point(v[4], toPoint(centre));
  const auto at = [&](int i, int j) { return v[std::size_t(3 * j + i)]; };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      block.add_face(at(i, j), at(i + 1, j), at(i, j + 1));
      block.add_face(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return block;
}

// The overlapping faces are removed, the centre they put on the patch's boundary moves onto the
// tip, and the gap left closes: the square is covered once, every face up.
TEST(Weld, PatchFacesOverlappingAnEarAreRemovedAndTheCentreMovesOntoItsTip) {
  const TriMesh grid = test::unitSquareGrid(10);
  const Cut c = earHole(grid);
  const TriMesh patch = otherDiagonalBlock({0.49, 0.51, 0});
  const auto result = weld(c.holed, holeLoop(c.holed), patch);
  EXPECT_EQ(result.earSplits, 0u);
  EXPECT_GE(result.trimmedFaces, 2u);
  EXPECT_EQ(result.snappedVertices, 1u);
  expectManifoldWithLoops(result.mesh, 1, test::topology(grid).eulerCharacteristic);
  EXPECT_NEAR(test::surfaceArea(result.mesh), 1.0, 1e-12);  // nothing overlaps, nothing is left
  expectFacingUp(result.mesh, 0);
  std::vector<int> faces(result.mesh.n_faces());
  std::iota(faces.begin(), faces.end(), 0);
  EXPECT_EQ(selfIntersections(result.mesh, faces, 1e-12), 0u);
  for (auto v : c.holed.vertices())
    EXPECT_EQ(result.mesh.point(v), c.holed.point(v));
  // The centre is the tip now: the patch adds no vertex.
  EXPECT_EQ(result.mesh.n_vertices(), c.holed.n_vertices());
}

TEST(Weld, AShrunkPatchIsJoinedByAStripOfBothLoopsLengths) {
  const Cut c = cut(test::unitSquareGrid(10), inCentreSquare);
  const TriMesh patch = shrunk(c.patch, {0.5, 0.5, 0}, 0.1);
  const auto result = weld(c.holed, holeLoop(c.holed), patch);
  EXPECT_EQ(result.sharedVertices, 0u);
  EXPECT_EQ(result.stripFaces, 32u);  // |a| + |b| = 16 + 16
  EXPECT_FALSE(result.patchFlipped);
  EXPECT_EQ(result.mesh.n_vertices(), c.holed.n_vertices() + patch.n_vertices());
  EXPECT_EQ(result.mesh.n_faces(), c.holed.n_faces() + patch.n_faces() + 32);
  expectManifoldWithLoops(result.mesh, 1, 1);
  expectFacingUp(result.mesh, int(c.holed.n_faces()));
  EXPECT_EQ(result.map.seamFaces.size(), 32u);
  for (int f : result.map.seamFaces)
    EXPECT_GE(f, int(c.holed.n_faces() + patch.n_faces()));
  EXPECT_EQ(result.trimmedFaces, 0u);
}

TEST(Weld, APatchSharingEveryOtherVertexGetsTwoTrianglesPerGap) {
  const Cut c = cut(test::unitSquareGrid(10), inCentreSquare);
  const auto patchLoop = boundaryLoops(c.patch).front();  // starts at a corner of the square
  ASSERT_EQ(patchLoop.size(), 16u);
  std::vector<char> odd(c.patch.n_vertices(), 0);
  for (std::size_t k = 1; k < patchLoop.size(); k += 2)
    odd[std::size_t(patchLoop[k])] = 1;
  const TriMesh patch =
      shrunk(c.patch, {0.5, 0.5, 0}, 0.2, [&](int v) { return odd[std::size_t(v)] != 0; });
  const auto result = weld(c.holed, holeLoop(c.holed), patch);
  EXPECT_EQ(result.sharedVertices, 8u);
  EXPECT_EQ(result.stripFaces, 16u);  // each gap a quad with three corners on the hole's side
  EXPECT_EQ(result.mesh.n_vertices(), c.holed.n_vertices() + patch.n_vertices() - 8);
  expectManifoldWithLoops(result.mesh, 1, 1);
  expectFacingUp(result.mesh, int(c.holed.n_faces()));  // none flat, none turned over
  EXPECT_EQ(result.trimmedFaces, 0u);
}

TEST(Weld, AReversedPatchIsTurnedOver) {
  const TriMesh grid = test::unitSquareGrid(10);
  const Cut c = cut(grid, inCentreSquare);
  const auto exact = weld(c.holed, holeLoop(c.holed), flipped(c.patch));
  EXPECT_TRUE(exact.patchFlipped);
  EXPECT_EQ(exact.sharedVertices, 16u);
  EXPECT_EQ(exact.stripFaces, 0u);
  expectManifoldWithLoops(exact.mesh, 1, 1);
  EXPECT_EQ(faceSet(exact.mesh), faceSet(grid));

  const auto apart = weld(c.holed, holeLoop(c.holed), flipped(shrunk(c.patch, {0.5, 0.5, 0}, 0.1)));
  EXPECT_TRUE(apart.patchFlipped);
  EXPECT_EQ(apart.stripFaces, 32u);
  expectManifoldWithLoops(apart.mesh, 1, 1);
  expectFacingUp(apart.mesh, int(c.holed.n_faces()));
}

TEST(Weld, ASphereCapHoleIsClosedByTheRemovedCap) {
  const TriMesh sphere = test::icosphere(3);
  const Cut c = cut(sphere, [](const Vector3d& p) { return p.z() > 0.8; });
  const auto loops = boundaryLoops(c.holed);
  ASSERT_EQ(loops.size(), 1u);
  const auto result = weld(c.holed, loops.front(), c.patch);
  EXPECT_EQ(result.sharedVertices, loops.front().size());
  EXPECT_EQ(result.stripFaces, 0u);
  EXPECT_EQ(result.mesh.n_vertices(), sphere.n_vertices());
  EXPECT_EQ(result.mesh.n_faces(), sphere.n_faces());
  expectManifoldWithLoops(result.mesh, 0, 2);
  EXPECT_EQ(faceSet(result.mesh), faceSet(sphere));
  EXPECT_NEAR(test::signedVolume(result.mesh), test::signedVolume(sphere), 1e-12);

  // The cap drawn 10% toward its pole: no vertex shared, the strip closes the sphere.
  const TriMesh sunk = shrunk(c.patch, Vector3d::UnitZ(), 0.1);
  const auto zipped = weld(c.holed, loops.front(), sunk);
  EXPECT_EQ(zipped.sharedVertices, 0u);
  EXPECT_EQ(zipped.stripFaces, 2 * loops.front().size());
  expectManifoldWithLoops(zipped.mesh, 0, 2);
  EXPECT_GT(test::signedVolume(zipped.mesh), 0.95 * test::signedVolume(sphere));
  EXPECT_EQ(zipped.trimmedFaces, 0u);
}

// Around a round hole's notches (ears of the staircase border), zipping a shrunk patch's loop to
// the border's would cross the strip's triangles: the weld refuses rather than fold the seam.
TEST(Weld, AZipThatWouldCrossItselfAroundTheBordersNotchesIsRefused) {
  const Cut c = cut(test::unitSquareGrid(12),
                    [](const Vector3d& p) { return (p - Vector3d(0.5, 0.5, 0)).norm() < 0.3; });
  try {
    weld(c.holed, holeLoop(c.holed), shrunk(c.patch, {0.5, 0.5, 0}, 0.05));
    ADD_FAILURE() << "welded a seam whose faces intersect";
  } catch (const WeldError& e) {
    EXPECT_EQ(e.port(), "patch");
    EXPECT_NE(std::string(e.what()).find("pairs of faces intersect"), std::string::npos)
        << e.what();
  }
}

TEST(Weld, IsDeterministic) {
  const Cut c = cut(test::unitSquareGrid(10), inCentreSquare);
  const TriMesh patch = shrunk(c.patch, {0.5, 0.5, 0}, 0.05);
  const auto a = weld(c.holed, holeLoop(c.holed), patch);
  const auto b = weld(c.holed, holeLoop(c.holed), patch);
  EXPECT_TRUE(test::bitIdentical(a.mesh, b.mesh));
  EXPECT_EQ(a.map.seamFaces, b.map.seamFaces);
}

MeshPtr caseMesh(const std::string& name) {
  return readMesh(test::meshPath(name)).mesh;
}

// A shared case: the mesh with a hole cut out and the removed faces, whose boundary vertices are
// the hole's; the weld restores the whole mesh.
void expectRestores(const std::string& whole, const std::string& hole, const std::string& patch) {
  const MeshPtr original = caseMesh(whole), holed = caseMesh("cases/" + hole),
                removed = caseMesh("cases/" + patch);
  auto border = std::make_shared<BorderLoop>();
  border->mesh = holed;
  const auto loops = boundaryLoops(holed->surface);
  ASSERT_EQ(loops.size(), 1u);
  border->vertex = loops.front();
  const test::NodeRun run =
      test::runNode("geobrush.weld", {{"border", border}, {"patch", removed}});
  const auto mesh = run.get<Mesh>("mesh");
  const auto map = run.get<PasteMap>("paste_map");
  const auto report = run.get<Metrics>("report");
  ASSERT_TRUE(mesh && map && report);
  EXPECT_TRUE(run.warnings.empty());
  EXPECT_EQ(report->values.at("shared_vertices"), double(loops.front().size()));
  EXPECT_EQ(report->values.at("strip_faces"), 0.0);
  EXPECT_EQ(report->values.at("patch_flipped"), 0.0);
  const auto topo = test::topology(mesh->surface), want = test::topology(original->surface);
  EXPECT_EQ(topo.vertices, want.vertices);
  EXPECT_EQ(topo.faces, want.faces);
  EXPECT_EQ(topo.edges, want.edges);
  EXPECT_EQ(topo.eulerCharacteristic, want.eulerCharacteristic);  // the genus restored
  EXPECT_EQ(topo.boundaryLoops, want.boundaryLoops);
  EXPECT_EQ(topo.nonManifoldVertices, 0u);
  EXPECT_EQ(topo.components, want.components);
  EXPECT_EQ(faceSet(mesh->surface), faceSet(original->surface));
  EXPECT_EQ(map->targetVertex.size(), mesh->surface.n_vertices());
  EXPECT_FALSE(map->seamFaces.empty());
}

TEST(WeldNode, RestoresTheBunnyFromItsBackHoleAndTheRemovedPatch) {
  expectRestores("bunny_small.obj", "bunny_small_back_hole.obj",
                 "bunny_small_back_removed_patch.obj");
}

TEST(WeldNode, RestoresNefertitisForehead) {
  expectRestores("nefertiti.obj", "nefertiti_forehead_hole.obj",
                 "nefertiti_forehead_removed_patch.obj");
}

// The node's error, naming its port, when it refuses.
std::string refusal(const ValuePtr& border, const ValuePtr& patch) {
  try {
    test::runNode("geobrush.weld", {{"border", border}, {"patch", patch}});
  } catch (const NodeError& e) {
    return e.where() + ": " + e.what();
  }
  return "accepted";
}

TEST(WeldNode, WarnsWhenItTurnsThePatchOver) {
  const Cut c = cut(test::unitSquareGrid(10), inCentreSquare);
  auto border = std::make_shared<BorderLoop>();
  border->mesh = std::make_shared<const Mesh>(c.holed);
  border->vertex = holeLoop(c.holed);
  const auto run = test::runNode(
      "geobrush.weld",
      {{"border", border}, {"patch", std::make_shared<const Mesh>(flipped(c.patch))}});
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(run.warnings[0], "turned over"));
  EXPECT_EQ(run.get<Metrics>("report")->values.at("patch_flipped"), 1.0);
}

TEST(WeldNode, RefusesInputsThatCannotBeWeldedNamingThePort) {
  const Cut c = cut(test::unitSquareGrid(10), inCentreSquare);
  auto border = std::make_shared<BorderLoop>();
  border->mesh = std::make_shared<const Mesh>(c.holed);
  border->vertex = holeLoop(c.holed);

  const auto closed = std::make_shared<const Mesh>(test::icosphere(1));
  EXPECT_TRUE(
      test::contains(refusal(border, closed), "input 'patch': the patch has 0 boundary loops"));

  const Cut ring = cut(test::unitSquareGrid(10), [](const Vector3d& p) {
    return std::abs(p.x() - 0.5) < 0.4 && std::abs(p.y() - 0.5) < 0.4 && !inCentreSquare(p);
  });
  const auto annulus = std::make_shared<const Mesh>(ring.patch);
  EXPECT_TRUE(
      test::contains(refusal(border, annulus), "input 'patch': the patch has 2 boundary loops"));

  // Two boundary vertices of the exact patch swapped: shared, but out of the border's order.
  TriMesh tangled = c.patch;
  const auto loop = boundaryLoops(tangled).front();
  const auto p1 = tangled.point(TriMesh::VertexHandle(loop[1]));
  tangled.set_point(TriMesh::VertexHandle(loop[1]), tangled.point(TriMesh::VertexHandle(loop[3])));
  tangled.set_point(TriMesh::VertexHandle(loop[3]), p1);
  EXPECT_TRUE(test::contains(refusal(border, std::make_shared<const Mesh>(tangled)),
                             "input 'patch': the patch's boundary vertices on the border are not "
                             "in the border's cyclic order"));

  // The hole's loop given with another mesh than the one it bounds.
  auto elsewhere = std::make_shared<BorderLoop>(*border);
  elsewhere->mesh = std::make_shared<const Mesh>(test::unitSquareGrid(10));
  EXPECT_TRUE(test::contains(refusal(elsewhere, std::make_shared<const Mesh>(c.patch)),
                             "input 'border': not a boundary loop of the holed mesh"));
  auto empty = std::make_shared<BorderLoop>();
  EXPECT_TRUE(
      test::contains(refusal(empty, std::make_shared<const Mesh>(c.patch)), "input 'border'"));

  // Two patch boundary vertices on one border vertex.
  TriMesh doubled = c.patch;
  doubled.set_point(TriMesh::VertexHandle(loop[1]),
                    doubled.point(TriMesh::VertexHandle(loop[0])) + TriMesh::Point(1e-9, 0, 0));
  EXPECT_TRUE(test::contains(refusal(border, std::make_shared<const Mesh>(doubled)),
                             "both lie on border vertex"));
}

}  // namespace
}  // namespace geobrush
