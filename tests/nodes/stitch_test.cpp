// geobrush.stitch: R_in pasted into the target as one manifold mesh.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/stitch.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "roi.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

std::shared_ptr<Parameterization> flatSquare(int n) {
  return test::heightFieldParameterization(n, [](double, double) { return 0.0; });
}

// A disc of a flat square of n x n quads around the quad (i, j) as the target canvas, uv its
// points' x and y.
std::shared_ptr<Parameterization> flatDiscAround(const MeshPtr& square, int n, int i, int j,
                                                 double radius) {
  return test::flatDiscParameterization(square, 2 * (j * n + i), radius);
}

// A disc of the flat square [-1, 1]^2 of n x n quads as the target canvas, the rest of the square
// outside it: a paste changes the canvas and joins it to the part outside.
std::shared_ptr<Parameterization> flatDiscOnSquare(int n, double radius) {
  return flatDiscAround(test::heightGrid(n, [](double, double) { return 0.0; }), n, n / 2, n / 2,
                        radius);
}

Strokes strokes(std::vector<Dab> dabs) {
  Strokes s;
  s.dabs = std::move(dabs);
  return s;
}

// Twice the signed area of each face projected on the xy plane.
std::vector<double> projectedAreas(const TriMesh& mesh) {
  std::vector<double> areas;
  for (auto f : mesh.faces()) {
    std::vector<Eigen::Vector2d> c;
    for (auto v : mesh.fv_range(f))
      c.emplace_back(mesh.point(v)[0], mesh.point(v)[1]);
    const Eigen::Vector2d a = c[1] - c[0], b = c[2] - c[0];
    areas.push_back(a.x() * b.y() - a.y() * b.x());
  }
  return areas;
}

void expectOneManifoldDisc(const TriMesh& mesh) {
  const MeshStats stats = meshStats(mesh);
  EXPECT_EQ(stats.boundaryLoops, 1u);
  EXPECT_EQ(stats.components, 1u);
  EXPECT_EQ(stats.isolatedVertices, 0u);
  EXPECT_EQ(stats.nonFiniteVertices, 0u);
  EXPECT_EQ(stats.eulerCharacteristic, 1);
  EXPECT_EQ(test::topology(mesh).nonManifoldVertices, 0u);
}

Eigen::Vector3d faceNormal(const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::vector<Eigen::Vector3d> c;
  for (auto v : mesh.fv_range(f))
    c.emplace_back(mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]);
  return (c[1] - c[0]).cross(c[2] - c[0]).normalized();
}

// The largest angle, in degrees, between the normals of two faces sharing an edge of a seam face.
double maxSeamNormalJump(const TriMesh& mesh, const std::vector<int>& seamFaces) {
  double largest = 0;
  for (int f : seamFaces)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
      const auto other = mesh.opposite_face_handle(h);
      if (!other.is_valid()) continue;
      const double c = faceNormal(mesh, TriMesh::FaceHandle(f)).dot(faceNormal(mesh, other));
      largest = std::max(largest, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI);
    }
  return largest;
}

// The seam strips' faces whose normal leans more than `degrees` away from +z.
std::size_t tiltedSeamFaces(const TriMesh& mesh, const std::vector<int>& seamFaces,
                            double degrees) {
  std::size_t tilted = 0;
  for (int f : seamFaces)
    tilted += faceNormal(mesh, TriMesh::FaceHandle(f)).z() < std::cos(degrees * M_PI / 180);
  return tilted;
}

StitchOptions refining() {
  StitchOptions options;
  options.seamRefinementRatio = 2;
  return options;
}

}  // namespace

// A flat source pasted flat into a flat target of another resolution: the result is the target
// disc again, and every face, seam strip included, keeps its orientation.
TEST(Stitch, FlatPasteIsOneManifoldDiscWithoutFolds) {
  auto source = flatSquare(24);
  auto target = flatSquare(17);
  const RoiResult roi =
      paintRegion(strokes({{{0.1, 0.05}, 0.55, false}}), *source, *target, RoiOptions{64});
  const StitchResult result =
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
  expectOneManifoldDisc(result.mesh);
  EXPECT_EQ(result.seamLoops, 1u);
  EXPECT_EQ(result.patchVertices, roi.region.sourceVertices.size());
  EXPECT_GT(result.gapTriangles, 0u);
  for (double area : projectedAreas(result.mesh))
    EXPECT_GT(area, 0);
  EXPECT_NEAR(test::surfaceArea(result.mesh), 4.0, 1e-9);
}

TEST(Stitch, PatchVerticesGoToTheDraftPlusTheOffset) {
  auto source = flatSquare(20);
  auto target = flatSquare(20);
  const RoiResult roi =
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *source, *target, RoiOptions{48});
  TriMesh draft = source->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[2] = 0.3 * draft.point(v)[0];
  Field2D offset;
  offset.grid = roi.region.grid;
  offset.values.assign(offset.grid.nodeCount(), Eigen::Vector3d(0, 0, 0.1));
  offset.defined.assign(offset.grid.nodeCount(), 1);
  const StitchResult result = stitchPaste(roi.region, *source, draft, &offset, *target);
  expectOneManifoldDisc(result.mesh);
  const std::size_t first = result.mesh.n_vertices() - result.patchVertices;
  for (std::size_t k = 0; k < result.patchVertices; ++k) {
    const auto& p = result.mesh.point(TriMesh::VertexHandle(int(first + k)));
    EXPECT_NEAR(p[2], 0.3 * p[0] + 0.1, 1e-12);
  }
}

// The layout, made before the draft and the offset exist, and the placement after them give the
// paste bit for bit: connectivity, every position, the map.
TEST(Stitch, LayoutThenPlacementIsThePaste) {
  auto source = test::heightFieldParameterization(
      24, [](double x, double y) { return 0.05 * std::sin(7 * x) * std::cos(5 * y); });
  auto target = test::heightFieldParameterization(
      19, [](double x, double y) { return 0.2 * (x * x + y * y); });
  const RoiResult roi =
      paintRegion(strokes({{{0.1, 0}, 0.55, false}}), *source, *target, RoiOptions{40});
  TriMesh draft = source->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[2] += 0.1 + 0.2 * draft.point(v)[1];
  Field2D offset;
  offset.grid = roi.region.grid;
  offset.defined.assign(offset.grid.nodeCount(), 1);
  for (int j = 0; j < offset.grid.height; ++j)
    for (int i = 0; i < offset.grid.width; ++i)
      offset.values.push_back(Eigen::Vector3d(0.01 * i, -0.02 * j, 0.03));
  const StitchResult paste = stitchPaste(roi.region, *source, draft, &offset, *target);
  ASSERT_GT(paste.patchVertices, 50u);

  TriMesh laidOut;
  const StitchResult layout = stitchLayoutInto(laidOut, roi.region, *source, *target);
  ASSERT_EQ(layout.map.sourceVertex, paste.map.sourceVertex);
  EXPECT_EQ(layout.map.targetVertex, paste.map.targetVertex);
  EXPECT_EQ(layout.map.seamFaces, paste.map.seamFaces);
  placePatch(laidOut, layout.map, *source, draft, &offset);
  ASSERT_EQ(laidOut.n_vertices(), paste.mesh.n_vertices());
  ASSERT_EQ(laidOut.n_faces(), paste.mesh.n_faces());
  for (auto v : laidOut.vertices())
    ASSERT_EQ(laidOut.point(v), paste.mesh.point(v)) << "vertex " << v.idx();
  for (auto f : laidOut.faces()) {
    std::vector<int> a, b;
    for (auto v : laidOut.fv_range(f))
      a.push_back(v.idx());
    for (auto v : paste.mesh.fv_range(f))
      b.push_back(v.idx());
    ASSERT_EQ(a, b) << "face " << f.idx();
  }
  // A map made for another mesh is refused rather than half applied.
  PasteMap shorter = layout.map;
  shorter.sourceVertex.pop_back();
  EXPECT_THROW(placePatch(laidOut, shorter, *source, draft, &offset), StitchError);
}

// An annulus: R_in has two boundary loops, and the target keeps an island inside it.
TEST(Stitch, AnAnnulusIsZippedAlongBothLoops) {
  auto source = flatSquare(30);
  auto target = flatSquare(22);
  const RoiResult roi = paintRegion(strokes({{{0, 0}, 0.7, false}, {{0.05, 0}, 0.3, true}}),
                                    *source, *target, RoiOptions{64});
  const StitchResult result =
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
  EXPECT_EQ(result.seamLoops, 2u);
  expectOneManifoldDisc(result.mesh);
  for (double area : projectedAreas(result.mesh))
    EXPECT_GT(area, 0);
}

TEST(Stitch, DisjointDabsArePastedEach) {
  auto source = flatSquare(24);
  auto target = flatSquare(24);
  const RoiResult roi =
      paintRegion(strokes({{{-0.5, -0.5}, 0.3, false}, {{0.5, 0.4}, 0.25, false}}), *source,
                  *target, RoiOptions{64});
  const StitchResult result =
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
  EXPECT_EQ(result.seamLoops, 2u);
  expectOneManifoldDisc(result.mesh);
}

// The paste map names the origin of every vertex and the faces of the seam strips.
TEST(Stitch, TheMapTellsTargetPasteAndSeamApart) {
  auto source = flatSquare(24);
  auto target = flatSquare(17);
  const RoiResult roi =
      paintRegion(strokes({{{0.1, 0.05}, 0.55, false}}), *source, *target, RoiOptions{64});
  TriMesh draft = source->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[2] = 0.25;
  const StitchResult result = stitchPaste(roi.region, *source, draft, nullptr, *target);
  const PasteMap& map = result.map;
  const TriMesh& mesh = result.mesh;
  ASSERT_EQ(map.targetVertex.size(), mesh.n_vertices());
  ASSERT_EQ(map.sourceVertex.size(), mesh.n_vertices());
  std::size_t pasted = 0;
  for (auto v : mesh.vertices()) {
    const int t = map.targetVertex[std::size_t(v.idx())],
              s = map.sourceVertex[std::size_t(v.idx())];
    EXPECT_NE(t >= 0, s >= 0);
    if (t >= 0) {
      EXPECT_EQ(mesh.point(v), target->canvas->surface.point(TriMesh::VertexHandle(t)));
    } else {
      EXPECT_EQ(mesh.point(v), draft.point(TriMesh::VertexHandle(s)));
      ++pasted;
    }
  }
  EXPECT_EQ(pasted, result.patchVertices);
  ASSERT_EQ(map.seamFaces.size(), result.gapTriangles);
  for (int f : map.seamFaces) {
    int fromTarget = 0;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      fromTarget += map.targetVertex[std::size_t(v.idx())] >= 0;
    EXPECT_TRUE(fromTarget == 1 || fromTarget == 2) << "face " << f;
  }
}

TEST(Stitch, AnEmptyRegionLeavesTheTargetUnchanged) {
  auto source = flatSquare(8);
  auto target = flatSquare(9);
  const RoiResult roi = paintRegion(Strokes(), *source, *target, RoiOptions{32});
  const StitchResult result =
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
  EXPECT_TRUE(test::bitIdentical(result.mesh, target->canvas->surface));
  EXPECT_EQ(result.map.targetVertex.size(), target->canvas->surface.n_vertices());
  EXPECT_EQ(result.map.targetVertex.back(), int(target->canvas->surface.n_vertices()) - 1);
  EXPECT_TRUE(result.map.seamFaces.empty());
}

TEST(Stitch, RefusesADraftOfAnotherCanvas) {
  auto source = flatSquare(8);
  const RoiResult roi =
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *source, *source, RoiOptions{32});
  EXPECT_THROW(stitchPaste(roi.region, *source, flatSquare(9)->canvas->surface, nullptr, *source),
               StitchError);
}

// A region painted on larger canvases names vertices the stitch's canvases do not have: refused
// with the vertex named, never read out of bounds.
TEST(Stitch, RefusesARegionPaintedOnOtherCanvases) {
  auto large = flatSquare(16);
  auto small = flatSquare(8);
  const RoiResult roi =
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *large, *large, RoiOptions{32});
  ASSERT_FALSE(roi.region.empty());
  for (const auto& [source, target] : {std::pair{small, large}, std::pair{large, small}}) {
    try {
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
      ADD_FAILURE() << "refused nothing";
    } catch (const StitchError& e) {
      EXPECT_THAT(e.what(), testing::HasSubstr("painted on other canvases"));
      EXPECT_THAT(e.what(), testing::HasSubstr(source == small ? "source canvas vertex"
                                                               : "target canvas vertex"));
    }
  }
  // Its own canvases take it.
  EXPECT_NO_THROW(stitchPaste(roi.region, *large, large->canvas->surface, nullptr, *large));
  EXPECT_NO_THROW(requireRegionOn(roi.region, large->uv.size()));
  EXPECT_THROW(requireRegionOn(roi.region, small->uv.size()), std::invalid_argument);
}

TEST(StitchNode, RefusesAnOffsetOnAnotherGrid) {
  const NodeType* type = test::registry().find("geobrush.stitch");
  ASSERT_TRUE(type);
  auto param = flatSquare(8);
  auto region = std::make_shared<Region2D>(
      paintRegion(strokes({{{0, 0}, 0.5, false}}), *param, *param, RoiOptions{32}).region);
  auto offset = std::make_shared<Field2D>();
  offset->grid = roiGrid(*param, 40);
  test::DirectContext ctx(*type, {{"region", region},
                                  {"source", param},
                                  {"draft", std::make_shared<const Mesh>(param->canvas->surface)},
                                  {"target", param},
                                  {"offset", offset}});
  try {
    test::run(type->create(), ctx);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'offset'");
  }
}

// The mountain's relief, lifted, pasted back into itself: the seam joins two irregular outlines.
TEST(Stitch, PastesIntoARealTerrain) {
  auto terrain = test::terrainParameterization();
  Eigen::Vector2d lo = terrain->uv.front(), hi = lo;
  for (const auto& u : terrain->uv) {
    lo = lo.cwiseMin(u);
    hi = hi.cwiseMax(u);
  }
  const Eigen::Vector2d centre = (lo + hi) / 2;
  const double radius = 0.25 * (hi - lo).minCoeff();
  const RoiResult roi = paintRegion(
      strokes({{centre, radius, false}, {centre + Eigen::Vector2d(radius, 0), radius / 2, false}}),
      *terrain, *terrain);
  TriMesh draft = terrain->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[1] += 0.05 * (hi - lo).minCoeff();
  const StitchResult result = stitchPaste(roi.region, *terrain, draft, nullptr, *terrain);
  const TriMesh& original = terrain->canvas->surface;
  const MeshStats before = meshStats(original), after = meshStats(result.mesh);
  EXPECT_EQ(after.boundaryLoops, before.boundaryLoops);
  EXPECT_EQ(after.components, before.components);
  EXPECT_EQ(after.eulerCharacteristic, before.eulerCharacteristic);
  EXPECT_EQ(after.nonFiniteVertices, 0u);
  EXPECT_EQ(after.isolatedVertices, 0u);
  EXPECT_EQ(test::topology(result.mesh).nonManifoldVertices, 0u);
  EXPECT_EQ(result.seamLoops, 1u);
  EXPECT_GT(result.removedFaces, 100u);
}

// The node builds straight into its output value; the mesh is the algorithm's.
TEST(StitchNode, OutputsWhatStitchPasteMakes) {
  const NodeType* type = test::registry().find("geobrush.stitch");
  ASSERT_TRUE(type);
  auto source = flatSquare(24);
  auto target = flatSquare(17);
  auto region = std::make_shared<Region2D>(
      paintRegion(strokes({{{0.1, 0.05}, 0.55, false}}), *source, *target, RoiOptions{64}).region);
  test::DirectContext ctx(*type, {{"region", region},
                                  {"source", source},
                                  {"draft", std::make_shared<const Mesh>(source->canvas->surface)},
                                  {"target", target}});
  test::run(type->create(), ctx);
  const auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("mesh"));
  ASSERT_TRUE(mesh);
  const StitchResult direct =
      stitchPaste(*region, *source, source->canvas->surface, nullptr, *target);
  EXPECT_TRUE(test::bitIdentical(mesh->surface, direct.mesh));
  const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs.at("map"));
  ASSERT_TRUE(map);
  EXPECT_EQ(map->sourceVertex, direct.map.sourceVertex);
}

// A brush's dabs start from the target's outside part, copied or taken back from a retired
// result that nothing holds any more, its paste map's arrays with it where nothing holds the map
// either: each result and map is still what a fresh stitch makes, halfedge
// for halfedge and entry for entry, dab after dab, with results or maps held elsewhere, an empty
// region and a change of target between them.
// The base a node derives for `target` (derivedStitchBase): the outside of the canvas' cell.
StitchBase freshNodeBase(const Parameterization& target) {
  const TriMesh& mesh = target.canvas->source->surface;
  return stitchBase(target, nullptr,
                    std::make_shared<const StitchOutside>(
                        stitchOutside(mesh, openFaces(mesh, openCellOf(*target.canvas)))));
}

// The outsides a series of target canvases asks for, as derivedStitchBase asks: each canvas'
// cell's, and the cell beyond the face its origin heads for, from the last origin seen in its cell
// (or in the cell before, which asked for this one).
class OutsidesAsked {
 public:
  // How many outsides `canvas` asks for that no canvas before it did.
  std::size_t ask(const Canvas& canvas) {
    const OpenCell cell = openCellOf(canvas);
    const Eigen::Vector3d origin = canvas.originPoint;
    std::size_t added = asked_.insert(cell.key).second;
    const auto before = lastOrigin_.find(cell.key);
    if (before != lastOrigin_.end()) {
      const OpenCell next = nextOpenCell(cell, origin, origin - before->second);
      if (next.key != 0) {
        added += asked_.insert(next.key).second;
        lastOrigin_[next.key] = origin;
      }
    }
    lastOrigin_[cell.key] = origin;
    return added;
  }
  bool has(Hash cell) const { return asked_.count(cell) > 0; }
  std::size_t size() const { return asked_.size(); }

 private:
  std::set<Hash> asked_;
  std::map<Hash, Eigen::Vector3d> lastOrigin_;
};

TEST(StitchNode, DabAfterDabMakesWhatAFreshStitchMakes) {
  const NodeType* type = test::registry().find("geobrush.stitch");
  ASSERT_TRUE(type);
  auto source = flatSquare(24);
  const auto draft = std::make_shared<const Mesh>(source->canvas->surface);
  const auto node = type->create();
  const auto derived =
      std::make_shared<DerivedStore>();  // kept from dab to dab, as an evaluator keeps it
  const auto bin = std::make_shared<RecycleBin>();  // each dab's results retired at its end
  std::vector<Dab> dabs;
  const auto first = flatDiscOnSquare(17, 0.8), second = flatDiscOnSquare(19, 0.8);
  std::vector<const Mesh*> made;       // each dab's result, by address
  std::vector<const int*> mapEntries;  // each dab's map's targetVertex array, by address
  std::vector<std::shared_ptr<const Mesh>> held;
  std::shared_ptr<const PasteMap> heldMap;
  std::vector<std::size_t> binned;  // what the bin holds as each dab starts
  constexpr int kEmpty = 5, kMapHeld = 6, kNewTarget = 8;
  for (int dab = 0; dab < 10; ++dab) {
    SCOPED_TRACE(dab);
    binned.push_back(bin->size());
    const auto& target = dab < kNewTarget ? first : second;
    dabs.push_back({{-0.3 + 0.05 * dab, 0.02 * dab}, 0.2, false});
    auto region = std::make_shared<Region2D>();
    if (dab != kEmpty)
      *region = paintRegion(strokes(dabs), *source, *target, RoiOptions{64}).region;
    test::DirectContext ctx(
        *type, {{"region", region}, {"source", source}, {"draft", draft}, {"target", target}}, {},
        derived, bin);
    test::run(*node, ctx);
    const auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("mesh"));
    ASSERT_TRUE(mesh);
    const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs.at("map"));
    ASSERT_TRUE(map);
    made.push_back(mesh.get());
    mapEntries.push_back(map->targetVertex.data());
    if (dab == 2 || dab == 3) held.push_back(mesh);
    if (dab == kMapHeld) heldMap = map;
    const StitchBase base = freshNodeBase(*target);
    const StitchResult fresh =
        stitchPaste(*region, *source, source->canvas->surface, nullptr, *target, &base);
    EXPECT_TRUE(test::sameHalfedgeStructure(mesh->surface, fresh.mesh));
    EXPECT_EQ(map->targetVertex, fresh.map.targetVertex);
    EXPECT_EQ(map->sourceVertex, fresh.map.sourceVertex);
    EXPECT_EQ(map->seamFaces, fresh.map.seamFaces);
    EXPECT_TRUE(test::topology(mesh->surface).nonManifoldVertices == 0);
  }
  // A result the node took back is one that was still alive when the next was made: the same
  // address means it was recycled, not reallocated. Each dab recycles the one before it, which no
  // one holds here, but for the two held (dabs 2 and 3) and the empty region's result, which is
  // the whole target: the bin has nothing then. Dab 4 finds dab 3's result held and copies the
  // outside part, but lays it out with dab 3's paste map, which no one holds.
  EXPECT_EQ(made[1], made[0]);
  EXPECT_EQ(made[2], made[1]);
  EXPECT_NE(made[3], made[2]);
  EXPECT_NE(made[4], made[3]);
  EXPECT_EQ(mapEntries[4], mapEntries[3]);
  EXPECT_EQ(made[5], made[4]);
  EXPECT_EQ(binned[6], 0u);
  EXPECT_EQ(made[7], made[6]);
  EXPECT_EQ(made[9], made[8]);
  // So are the maps, but for the one held.
  EXPECT_EQ(mapEntries[1], mapEntries[0]);
  EXPECT_EQ(mapEntries[3], mapEntries[2]);
  EXPECT_NE(mapEntries[7], mapEntries[6]);
  EXPECT_EQ(mapEntries[9], mapEntries[8]);
}

// Pastes `painted` from `source` into `target` with `node` and the store `derived`, as an
// evaluator would, and checks the result against a fresh node's with a store of its own.
void pasteAsAFreshNodeDoes(const NodeType& type, geobrush::Node& node,
                           const std::shared_ptr<DerivedStore>& derived, const Strokes& painted,
                           const std::shared_ptr<Parameterization>& source, const MeshPtr& draft,
                           const std::shared_ptr<Parameterization>& target) {
  auto region =
      std::make_shared<Region2D>(paintRegion(painted, *source, *target, RoiOptions{64}).region);
  const std::map<std::string, ValuePtr, std::less<>> inputs = {
      {"region", region}, {"source", source}, {"draft", draft}, {"target", target}};
  test::DirectContext ctx(type, inputs, {}, derived);
  test::run(node, ctx);
  const auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("mesh"));
  ASSERT_TRUE(mesh);
  const auto freshNode = type.create();
  test::DirectContext fresh(type, inputs, {}, std::make_shared<DerivedStore>());
  test::run(*freshNode, fresh);
  EXPECT_TRUE(test::sameHalfedgeStructure(
      mesh->surface, std::dynamic_pointer_cast<const Mesh>(fresh.outputs.at("mesh"))->surface));
}

// Dragging the target canvas over one mesh: each move's base is derived data for its canvas, its
// outside part shared by the moves within one cell, and each result is a fresh node's, element
// for element, with no history used.
TEST(StitchNode, DraggingTheTargetCanvasGivesWhatAFreshNodeGives) {
  const NodeType* type = test::registry().find("geobrush.stitch");
  ASSERT_TRUE(type);
  auto source = flatSquare(24);
  const auto draft = std::make_shared<const Mesh>(source->canvas->surface);
  constexpr int n = 40;
  const MeshPtr square = test::heightGrid(n, [](double, double) { return 0.0; });
  const Strokes painted = strokes({{{0.0, 0.05}, 0.2, false}});
  const auto node = type->create();
  const auto derived = std::make_shared<DerivedStore>();
  std::set<Hash> cells;
  OutsidesAsked asked;
  for (int step = 0; step < 6; ++step) {
    SCOPED_TRACE(step);
    const auto target = flatDiscAround(square, n, 20 + step / 2, 20 + step % 2, 0.7);
    cells.insert(openCellOf(*target->canvas).key);
    asked.ask(*target->canvas);
    pasteAsAFreshNodeDoes(*type, *node, derived, painted, source, draft, target);
    EXPECT_FALSE(node->usedHistory());
  }
  // A base and a locator per target canvas, and an outside per cell: the canvases' one, and the
  // ones the moves headed for.
  EXPECT_EQ(cells.size(), 1u);
  EXPECT_EQ(derived->builds(), 12u + asked.size());
}

// A brush, then a drag across several cells. The brush's canvas stays: it builds no outside
// ahead. Once the canvas moves, each move whose origin heads for a near face asks for the outside
// beyond, and each move into a cell finds the cell's outside and builds only its base and
// locator; every result is a fresh node's.
TEST(StitchNode, ADragFindsTheOutsideOfEachCellItEnters) {
  const NodeType* type = test::registry().find("geobrush.stitch");
  ASSERT_TRUE(type);
  auto source = flatSquare(24);
  const auto draft = std::make_shared<const Mesh>(source->canvas->surface);
  constexpr int n = 80;  // steps of 0.025, under a fifth of the cells' side (0.177)
  const MeshPtr square = test::heightGrid(n, [](double, double) { return 0.0; });
  const Strokes painted = strokes({{{0.0, 0.05}, 0.2, false}});
  const auto node = type->create();
  const auto derived = std::make_shared<DerivedStore>();
  auto paste = [&](const std::shared_ptr<Parameterization>& target) {
    pasteAsAFreshNodeDoes(*type, *node, derived, painted, source, draft, target);
  };
  const int start = 30;
  const auto brushed = flatDiscAround(square, n, start, 39, 0.7);
  for (int dab = 0; dab < 3; ++dab)
    paste(brushed);
  EXPECT_EQ(derived->builds(), 3u);  // its base, its locator and its cell's outside
  OutsidesAsked asked;
  asked.ask(*brushed->canvas);
  int entered = 0;
  OpenCell last = openCellOf(*brushed->canvas);
  for (int i = start + 1; i <= start + 20; ++i) {
    SCOPED_TRACE(i);
    const auto target = flatDiscAround(square, n, i, 39, 0.7);
    const OpenCell cell = openCellOf(*target->canvas);
    if (cell.key != last.key) {
      ++entered;
      EXPECT_TRUE(asked.has(cell.key));
    }
    last = cell;
    const std::size_t newOutsides = asked.ask(*target->canvas);
    const std::uint64_t builds = derived->builds();
    paste(target);
    EXPECT_EQ(derived->builds() - builds, 2 + newOutsides);
  }
  EXPECT_GE(entered, 2);
}

// The faces of a mesh as sorted triples of their corners' points, in sorted order: equal for
// meshes that hold the same triangles in any order.
std::vector<std::array<std::array<double, 3>, 3>> triangleSet(const TriMesh& mesh) {
  std::vector<std::array<std::array<double, 3>, 3>> triangles;
  for (auto f : mesh.faces()) {
    std::array<std::array<double, 3>, 3> corners;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto& p = mesh.point(v);
      corners[std::size_t(k++)] = {p[0], p[1], p[2]};
    }
    std::sort(corners.begin(), corners.end());
    triangles.push_back(corners);
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

// An open part larger than the canvas (a cell's, as a drag shares it) gives the paste the canvas'
// own open part gives: the same triangles, in another order.
TEST(Stitch, AnOpenPartAroundTheCanvasGivesTheSamePaste) {
  auto source = flatSquare(47);
  const MeshPtr square = test::heightGrid(30, [](double, double) { return 0.0; });
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    const auto target = flatDiscAround(square, 30, 13 + step, 15, 0.6);
    const OpenCell cell = openCellOf(*target->canvas);
    const auto outside = std::make_shared<const StitchOutside>(
        stitchOutside(square->surface, openFaces(square->surface, cell)));
    const StitchBase shared = stitchBase(*target, nullptr, outside);
    ASSERT_EQ(shared.outside, outside);  // it holds the canvas
    EXPECT_GT(outside->openMeshFaces.size(), target->canvas->surface.n_faces());
    const StitchBase own = stitchBase(*target);
    EXPECT_EQ(own.outside->openMeshFaces.size(), target->canvas->surface.n_faces());
    const Region2D region =
        paintRegion(strokes({{{0.05 * step, 0.0}, 0.25, false}}), *source, *target, RoiOptions{96})
            .region;
    const StitchResult a =
        stitchPaste(region, *source, source->canvas->surface, nullptr, *target, &shared);
    const StitchResult b =
        stitchPaste(region, *source, source->canvas->surface, nullptr, *target, &own);
    EXPECT_TRUE(a.startsWithOutside);
    EXPECT_EQ(triangleSet(a.mesh), triangleSet(b.mesh));
    EXPECT_EQ(test::topology(a.mesh).nonManifoldVertices, 0u);
    EXPECT_EQ(test::topology(a.mesh).boundaryLoops, 1u);
  }
}

// The faces of `mesh` listed, as a target canvas parameterized by x and y; `boundary` is its
// longest boundary loop (the others are inner loops).
std::shared_ptr<Parameterization> flatCanvasOf(const MeshPtr& mesh, const std::vector<int>& faces) {
  Submesh sub = extractSubmesh(mesh->surface, faces);
  auto canvas = std::make_shared<Canvas>();
  canvas->source = mesh;
  canvas->surface = std::move(sub.surface);
  canvas->sourceVertex = std::move(sub.sourceVertex);
  canvas->sourceFace = std::move(sub.sourceFace);
  const TriMesh& surface = canvas->surface;
  std::set<int> traced;
  for (auto start : surface.halfedges()) {
    if (!surface.is_boundary(start) || traced.count(start.idx())) continue;
    std::vector<int> loop;
    for (auto h = start; loop.empty() || h != start; h = surface.next_halfedge_handle(h)) {
      traced.insert(h.idx());
      loop.push_back(surface.from_vertex_handle(h).idx());
    }
    if (loop.size() > canvas->boundary.size()) canvas->boundary = loop;
  }
  canvas->originFace = 0;
  canvas->originPoint = pointOf(surface, TriMesh::VertexHandle(0));
  auto param = std::make_shared<Parameterization>();
  for (auto v : surface.vertices()) {
    param->uv.emplace_back(surface.point(v)[0], surface.point(v)[1]);
    param->normal.push_back(Eigen::Vector3d::UnitZ());
  }
  param->canvas = canvas;
  return param;
}

// A cut whose kept faces meet at a vertex in two fans is made manifold by removing the faces
// there, which may reach beyond the open part: here the canvas misses one face at vertex b (an
// inner loop), and Q covers a C around b, two of b's neighbours but not the four between them.
// The kept faces at b are the missing face and the one across from it; the paste is then made on
// the whole target and gives what an open part holding every face gives.
TEST(Stitch, ACutMadeManifoldBeyondTheOpenPartGivesThePasteOfAnOpenPartHoldingIt) {
  constexpr int n = 20;
  const MeshPtr square = test::heightGrid(n, [](double, double) { return 0.0; });
  const TriMesh& mesh = square->surface;
  const auto at = [](int i, int j) { return j * (n + 1) + i; };
  const std::set<int> notchCorners = {at(10, 10), at(10, 11), at(9, 10)};  // b, its N and W
  int notch = -1;
  std::vector<int> faces;
  for (auto f : mesh.faces()) {
    std::set<int> corners;
    bool near = true;
    for (auto v : mesh.fv_range(f)) {
      corners.insert(v.idx());
      near = near && pointOf(mesh, v).norm() <= 0.55;
    }
    if (corners == notchCorners) notch = f.idx();
    if (near && corners != notchCorners) faces.push_back(f.idx());
  }
  ASSERT_GE(notch, 0);
  const auto target = flatCanvasOf(square, faces);
  const Canvas& canvas = *target->canvas;
  // The C: b's NE neighbour, around its E and S sides two rings out, to its SW neighbour.
  const std::vector<int> arc = {at(11, 11), at(12, 11), at(12, 10), at(12, 9),
                                at(11, 8),  at(10, 8),  at(9, 8),   at(9, 9)};
  Region2D region;
  for (int m : arc) {
    const auto it = std::find(canvas.sourceVertex.begin(), canvas.sourceVertex.end(), m);
    ASSERT_NE(it, canvas.sourceVertex.end());
    region.targetVertices.push_back(int(it - canvas.sourceVertex.begin()));
  }
  std::sort(region.targetVertices.begin(), region.targetVertices.end());
  const auto source = flatSquare(4 * n);
  const double spacing = 2.0 / n;
  for (auto v : source->canvas->surface.vertices()) {
    bool inQ = false;
    for (int m : arc)
      inQ = inQ ||
            (pointOf(source->canvas->surface, v) - pointOf(mesh, TriMesh::VertexHandle(m))).norm() <
                0.6 * spacing;
    if (inQ) region.sourceVertices.push_back(v.idx());
  }

  const StitchBase own = stitchBase(*target);
  ASSERT_EQ(own.outside->openMeshFaces, faces);
  const StitchBase whole = stitchBase(*target, nullptr,
                                      std::make_shared<const StitchOutside>(stitchOutside(
                                          mesh, std::vector<char>(mesh.n_faces(), 1))));
  const StitchResult a =
      stitchPaste(region, *source, source->canvas->surface, nullptr, *target, &own);
  const StitchResult b =
      stitchPaste(region, *source, source->canvas->surface, nullptr, *target, &whole);
  EXPECT_FALSE(a.startsWithOutside);  // made on the whole target
  EXPECT_TRUE(b.startsWithOutside);
  EXPECT_EQ(triangleSet(a.mesh), triangleSet(b.mesh));
  EXPECT_EQ(test::topology(a.mesh).nonManifoldVertices, 0u);
  EXPECT_EQ(test::topology(a.mesh).boundaryLoops, 1u);
  // The face outside the canvas is gone.
  const Eigen::Vector3d centre = (pointOf(mesh, TriMesh::VertexHandle(at(10, 10))) +
                                  pointOf(mesh, TriMesh::VertexHandle(at(10, 11))) +
                                  pointOf(mesh, TriMesh::VertexHandle(at(9, 10)))) /
                                 3;
  for (auto f : a.mesh.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : a.mesh.fv_range(f))
      c += pointOf(a.mesh, v) / 3;
    EXPECT_GT((c - centre).norm(), 1e-9);
  }
}

// A canvas with no extent, or far from the coordinate origin for its size, has no cell: its base
// opens its own faces.
TEST(Stitch, ADegenerateCanvasHasNoOpenCell) {
  Canvas point;
  for (int k = 0; k < 3; ++k)
    point.surface.add_vertex(TriMesh::Point(0.5, 0.5, 0.5));
  point.originPoint = Eigen::Vector3d(0.5, 0.5, 0.5);
  EXPECT_EQ(openCellOf(point).key, 0u);
  Canvas far;
  for (int k = 0; k < 3; ++k)
    far.surface.add_vertex(TriMesh::Point(1e20, 0.5, k == 1 ? 0.501 : 0.5));
  far.originPoint = Eigen::Vector3d(1e20, 0.5, 0.5);
  EXPECT_EQ(openCellOf(far).key, 0u);
  Canvas small = point;
  small.surface.set_point(TriMesh::VertexHandle(1), TriMesh::Point(0.5, 0.5, 0.5 + 1e-3));
  EXPECT_NE(openCellOf(small).key, 0u);
}

// The cell of a disc canvas on a plane: R bounds the canvas within a quarter octave, the centre
// is that of the cube of side R / 4 holding the origin, and its open part holds the canvas for an
// origin anywhere in the cell.
TEST(Stitch, AnOpenCellHoldsTheCanvasAndItsCellCentre) {
  const MeshPtr square = test::heightGrid(40, [](double, double) { return 0.0; });
  for (int i : {12, 20, 27}) {
    SCOPED_TRACE(i);
    const auto target = flatDiscAround(square, 40, i, 19, 0.5);
    const Canvas& canvas = *target->canvas;
    double farthest = 0;
    for (auto v : canvas.surface.vertices())
      farthest = std::max(farthest, (pointOf(canvas.surface, v) - canvas.originPoint).norm());
    const OpenCell cell = openCellOf(canvas);
    const double side = (cell.radius) / (4 + std::sqrt(3.0) / 2);  // radius = R + side sqrt(3) / 2
    const double r = 4 * side;
    EXPECT_GE(r, farthest);
    EXPECT_LT(r, std::pow(2.0, 0.25) * farthest);
    EXPECT_NEAR(std::log2(r) * 4, std::round(std::log2(r) * 4), 1e-9);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_LE(std::abs(canvas.originPoint[axis] - cell.center[axis]), side / 2 + 1e-12);
      const double index = cell.center[axis] / side - 0.5;
      EXPECT_NEAR(index, std::round(index), 1e-9);
    }
    const std::vector<char> open = openFaces(square->surface, cell);
    for (int f : canvas.sourceFace)
      EXPECT_TRUE(open[std::size_t(f)]) << f;
  }
}

// The cell a drag may enter next, on the lattice of a unit cell at the coordinate origin: the one
// across the face the origin reaches first going its way, where that is nearer than a fifth of a
// side; none for a drag that stays, or heads away from the near faces.
TEST(Stitch, TheCellADragMayEnterNextIsAcrossTheFaceItHeadsFor) {
  const OpenCell cell = openCellAt(8, Eigen::Vector3d(0.5, 0.5, 0.5));  // R = 4, side 1
  ASSERT_NE(cell.key, 0u);
  ASSERT_EQ(cell.side, 1.0);
  ASSERT_EQ(cell.center, Eigen::Vector3d(0.5, 0.5, 0.5));
  using V = Eigen::Vector3d;
  auto next = [&](const V& point, const V& direction) {
    return nextOpenCell(cell, point, direction);
  };
  EXPECT_EQ(next(V(0.9, 0.5, 0.5), V::Zero()).key, 0u);
  EXPECT_EQ(next(V(0.5, 0.5, 0.5), V(1, 0, 0)).key, 0u);
  EXPECT_EQ(next(V(0.79, 0.5, 0.5), V(1, 0, 0)).key, 0u);  // 0.21 from it, more than a fifth
  EXPECT_EQ(next(V(0.9, 0.5, 0.5), V(1, 0, 0)).center, V(1.5, 0.5, 0.5));
  EXPECT_EQ(next(V(0.9, 0.5, 0.5), V(-3, 0, 0)).key, 0u);  // away from the near face
  EXPECT_EQ(next(V(0.5, 0.5, 0.05), V(0, 0, -0.01)).center, V(0.5, 0.5, -0.5));
  // At 45 degrees 0.1 from the face x = 1 is 0.14 along the way, 0.15 is 0.21.
  EXPECT_EQ(next(V(0.9, 0.5, 0.5), V(1, 1, 0)).center, V(1.5, 0.5, 0.5));
  EXPECT_EQ(next(V(0.85, 0.5, 0.5), V(1, 1, 0)).key, 0u);
  // Near two faces, the one the way reaches first.
  EXPECT_EQ(next(V(0.9, 0.95, 0.5), V(1, 0.1, 0)).center, V(1.5, 0.5, 0.5));
  EXPECT_EQ(next(V(0.9, 0.95, 0.5), V(1, 1, 0)).center, V(0.5, 1.5, 0.5));
  // It is the cell a point just across that face lies in, of the same size.
  const OpenCell across = next(V(0.1, 0.95, 0.5), V(0, 1, 0));
  EXPECT_EQ(across.key, openCellAt(8, V(0.1, 1.01, 0.5)).key);
  EXPECT_EQ(across.radius, cell.radius);
  EXPECT_EQ(nextOpenCell(OpenCell{}, V(0.9, 0.5, 0.5), V(1, 0, 0)).key, 0u);
}

// A paste turned back into the target's outside part in place is what copyOutside makes, and a
// paste into it is what a fresh stitch makes, on a plain seam and on a refined one.
TEST(Stitch, APasteTurnedBackIntoTheOutsidePartIsItsCopy) {
  auto source = flatSquare(47);
  for (int n : {17, 8}) {
    SCOPED_TRACE(n);
    const auto target = flatDiscOnSquare(n, 0.9);
    const StitchBase base = stitchBase(*target);
    ASSERT_FALSE(base.outside->borderVertices.empty());
    const TriMesh& targetMesh = target->canvas->source->surface;
    TriMesh outside, reused;
    copyOutside(*base.outside, targetMesh, source->canvas->surface, outside);
    const StitchOptions options = n == 8 ? refining() : StitchOptions{};
    std::vector<Dab> dabs;
    int refinedDabs = 0;
    for (int dab = 0; dab < 3; ++dab) {
      SCOPED_TRACE(dab);
      dabs.push_back({{-0.1 + 0.1 * dab, 0.05 * dab}, 0.25, false});
      const Region2D region = paintRegion(strokes(dabs), *source, *target, RoiOptions{96}).region;
      if (dab == 0) {
        copyOutside(*base.outside, targetMesh, source->canvas->surface, reused);
      } else {
        restoreOutside(*base.outside, reused);
      }
      EXPECT_TRUE(test::sameHalfedgeStructure(reused, outside));
      const StitchResult made = stitchPasteInto(reused, region, *source, source->canvas->surface,
                                                nullptr, *target, &base, true, options);
      EXPECT_TRUE(made.startsWithOutside);
      refinedDabs += made.refinedVertices > 0;
      const StitchResult fresh =
          stitchPaste(region, *source, source->canvas->surface, nullptr, *target, &base, options);
      EXPECT_TRUE(test::sameHalfedgeStructure(reused, fresh.mesh));
      EXPECT_EQ(test::topology(reused).boundaryLoops, 1u);
    }
    // On the coarse target some dabs are refined along the seam, and some fall back to the
    // unrefined seam (the refined band cannot be joined there).
    EXPECT_EQ(refinedDabs > 0, n == 8);
  }
  TriMesh small;
  EXPECT_THROW(restoreOutside(*stitchBase(*flatDiscOnSquare(17, 0.8)).outside, small), StitchError);
}

// The longest edge of the seam faces.
double longestSeamEdge(const TriMesh& mesh, const std::vector<int>& seamFaces) {
  double longest = 0;
  for (int f : seamFaces)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f)))
      longest = std::max(longest, mesh.calc_edge_length(h));
  return longest;
}

// A fine flat patch pasted into a flat target of six by six big squares (section 4.4): without
// refinement the target's outline lies up to a square away from the patch's, and the strips
// between them fan many short patch edges onto a few long target ones (the greedy walk folded
// them over; the strip with the fewest turned triangles keeps them flat, but long); with it the
// faces along dQ are bisected down to the patch's edge length first, and every strip face keeps
// the plane's normal and is about as long as the patch's edges.
TEST(Stitch, ACoarseTargetIsRefinedAlongTheSeamSoThatNoStripFolds) {
  auto source = flatSquare(47);
  auto target = flatSquare(6);
  const RoiResult roi =
      paintRegion(strokes({{{0.1, 0.05}, 0.45, false}}), *source, *target, RoiOptions{96});
  const StitchResult coarse =
      stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
  EXPECT_EQ(tiltedSeamFaces(coarse.mesh, coarse.map.seamFaces, 90), 0u);

  const StitchResult refined = stitchPaste(roi.region, *source, source->canvas->surface, nullptr,
                                           *target, nullptr, refining());
  EXPECT_GT(refined.refinedVertices, 0u);
  EXPECT_EQ(tiltedSeamFaces(refined.mesh, refined.map.seamFaces, 2), 0u);
  EXPECT_LT(longestSeamEdge(refined.mesh, refined.map.seamFaces),
            0.5 * longestSeamEdge(coarse.mesh, coarse.map.seamFaces));
  EXPECT_LT(maxSeamNormalJump(refined.mesh, refined.map.seamFaces), 2);
  for (double area : projectedAreas(refined.mesh))
    EXPECT_GT(area, 0);
  // The refinement keeps the target's shape: the result still covers the square once.
  expectOneManifoldDisc(refined.mesh);
  EXPECT_NEAR(test::surfaceArea(refined.mesh), 4.0, 1e-9);
  EXPECT_EQ(refined.seamLoops, 1u);
}

// A region smaller than the target's faces, inside one pair of them, covers no target vertex: the
// target faces R_in's outline passes through are removed all the same, so that the patch replaces
// them instead of overlapping them, with and without the seam refinement.
TEST(Stitch, ARegionInsideOneCoarseFaceReplacesTheFacesUnderIt) {
  auto source = flatSquare(40);
  auto target = flatSquare(4);
  const RoiResult roi =
      paintRegion(strokes({{{0.3, 0.2}, 0.12, false}}), *source, *target, RoiOptions{96});
  ASSERT_TRUE(roi.region.targetVertices.empty());
  ASSERT_FALSE(roi.region.sourceVertices.empty());
  for (const StitchOptions& options : {StitchOptions(), refining()}) {
    const StitchResult result = stitchPaste(roi.region, *source, source->canvas->surface, nullptr,
                                            *target, nullptr, options);
    EXPECT_GT(result.removedFaces, 0u);
    EXPECT_EQ(result.seamLoops, 1u);
    expectOneManifoldDisc(result.mesh);
    // The square covered once: no face overlaps another.
    EXPECT_NEAR(test::surfaceArea(result.mesh), 4.0, 1e-9);
    for (double area : projectedAreas(result.mesh))
      EXPECT_GT(area, 0);
  }
}

// The vertices the refinement adds lie on the target's faces and come from neither mesh.
TEST(Stitch, RefinedVerticesLieOnTheTargetAndAreMappedToNeither) {
  auto source = flatSquare(48);
  auto target = test::heightFieldParameterization(4, [](double x, double y) { return x + 2 * y; });
  const RoiResult roi =
      paintRegion(strokes({{{-0.1, 0.1}, 0.6, false}}), *source, *target, RoiOptions{96});
  const StitchResult result = stitchPaste(roi.region, *source, source->canvas->surface, nullptr,
                                          *target, nullptr, refining());
  ASSERT_GT(result.refinedVertices, 0u);
  const PasteMap& map = result.map;
  std::size_t neither = 0;
  for (auto v : result.mesh.vertices()) {
    const int t = map.targetVertex[std::size_t(v.idx())],
              s = map.sourceVertex[std::size_t(v.idx())];
    if (t >= 0 || s >= 0) continue;
    ++neither;
    const auto& p = result.mesh.point(v);
    EXPECT_NEAR(p[2], p[0] + 2 * p[1], 1e-12);
  }
  EXPECT_EQ(neither, result.refinedVertices);
  const MeshStats stats = meshStats(result.mesh);
  EXPECT_EQ(stats.boundaryLoops, 1u);
  EXPECT_EQ(stats.nonFiniteVertices, 0u);
  EXPECT_EQ(test::topology(result.mesh).nonManifoldVertices, 0u);
}

// A target as fine as the source is never refined: the paste is bit for bit the unrefined one.
TEST(Stitch, AFineTargetIsNotRefined) {
  auto source = flatSquare(24);
  for (int n : {17, 24, 30}) {
    SCOPED_TRACE(n);
    auto target = flatSquare(n);
    const RoiResult roi =
        paintRegion(strokes({{{0.1, 0.05}, 0.55, false}}), *source, *target, RoiOptions{64});
    const StitchResult plain =
        stitchPaste(roi.region, *source, source->canvas->surface, nullptr, *target);
    const StitchResult refined = stitchPaste(roi.region, *source, source->canvas->surface, nullptr,
                                             *target, nullptr, refining());
    EXPECT_EQ(refined.refinedVertices, 0u);
    EXPECT_TRUE(test::bitIdentical(plain.mesh, refined.mesh));
    EXPECT_EQ(plain.map.seamFaces, refined.map.seamFaces);
  }
}

// The mountain's relief cloned onto a geodesic sphere of 362 vertices (the comparison graph with
// a coarse target): the refined seam bends far less than the unrefined one, and the result stays
// one closed manifold whose seam shares its vertices.
TEST(StitchNode, ACoarseSphereGetsAnUnfoldedSeam) {
  const auto graph = test::sourceDir() / "graphs" / "compare_mountain_sphere_membrane.json";
  const auto refined = test::graphMetrics(graph, {"target_mesh.resolution=6"});
  const auto unrefined =
      test::graphMetrics(graph, {"target_mesh.resolution=6", "stitch.seam_refinement=0"});
  ASSERT_TRUE(refined.count("seam_normal_jump_p95_deg"));
  ASSERT_TRUE(unrefined.count("seam_normal_jump_p95_deg"));
  EXPECT_GT(unrefined.at("seam_normal_jump_p95_deg"), 60);
  EXPECT_LT(refined.at("seam_normal_jump_p95_deg"), 0.5 * unrefined.at("seam_normal_jump_p95_deg"));
  EXPECT_EQ(refined.at("manifold"), 1);
  EXPECT_EQ(refined.at("components"), 1);
  EXPECT_EQ(refined.at("boundary_loops"), 0);
  EXPECT_EQ(refined.at("non_finite_vertices"), 0);
  EXPECT_EQ(refined.at("seam_unshared_vertices"), 0);
  EXPECT_EQ(refined.at("new_self_intersections"), 0);
}
