#include "belt_smooth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/laplacian.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/region.hpp"
#include "geobrush/vertex_fields.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// A plane whose central square |x|, |y| < 0.5 (the region) stands `step` higher.
struct Step {
  MeshPtr mesh;
  std::vector<std::uint8_t> inside;
};

Step raisedSquare(int n, double step) {
  const auto in = [](double x, double y) { return std::abs(x) < 0.5 && std::abs(y) < 0.5; };
  Step s;
  s.mesh = test::heightGrid(n, [&](double x, double y) { return in(x, y) ? step : 0.0; });
  for (auto v : s.mesh->surface.vertices())
    s.inside.push_back(in(s.mesh->surface.point(v)[0], s.mesh->surface.point(v)[1]));
  return s;
}

// The largest height difference across an edge.
double steepest(const TriMesh& mesh) {
  double jump = 0;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    jump = std::max(jump, std::abs(mesh.point(mesh.to_vertex_handle(h))[2] -
                                   mesh.point(mesh.from_vertex_handle(h))[2]));
  }
  return jump;
}

// Sec. 3.5: the belt is the vertices fewer than `rings` rings from an edge across the border;
// smoothing it softens the step while everything else keeps its bits.
TEST(BeltSmooth, SoftensTheStepAtTheBorderAndMovesNothingElse) {
  const Step s = raisedSquare(20, 0.1);
  const BeltSmoothResult result = smoothBelt(s.mesh->surface, s.inside, {});
  const TriMesh& before = s.mesh->surface;
  std::vector<std::uint8_t> inBelt(before.n_vertices(), 0);
  for (int v : result.belt)
    inBelt[std::size_t(v)] = 1;
  for (auto v : before.vertices()) {
    const auto& p = before.point(v);
    // Grid spacing 0.1: the step lies between 0.4 and 0.5 from the centre in x or y; the
    // border's vertices and one ring more on each side, so 0.3..0.6, make the belt (all of them
    // away from the square's corners, where the grid's diagonals run one way only).
    const double d = std::max(std::abs(p[0]), std::abs(p[1]));
    const bool near = d > 0.3 - 1e-9 && d < 0.6 + 1e-9;
    const bool belt = inBelt[std::size_t(v.idx())];
    if (belt) {
      EXPECT_TRUE(near) << p;
    }
    if (near && std::min(std::abs(p[0]), std::abs(p[1])) < 0.25) {
      EXPECT_TRUE(belt) << p;
    }
    if (!inBelt[std::size_t(v.idx())]) {
      EXPECT_EQ(result.mesh.point(v), p);
    }
  }
  EXPECT_LT(steepest(result.mesh), 0.6 * steepest(before));
  EXPECT_EQ(test::faceIndices(result.mesh), test::faceIndices(before));
  // Seam faces straddle the border.
  for (int f : result.seamFaces) {
    int in = 0;
    for (auto v : before.fv_range(TriMesh::FaceHandle(f)))
      in += s.inside[std::size_t(v.idx())];
    EXPECT_TRUE(in == 1 || in == 2);
  }
  EXPECT_FALSE(result.seamFaces.empty());
}

TEST(BeltSmooth, KeepsTheMeshBoundaryAndDoesNothingWithoutPasses) {
  const Step s = raisedSquare(10, 0.1);
  std::vector<std::uint8_t> nearEdge(s.inside.size(), 0);
  for (auto v : s.mesh->surface.vertices())
    nearEdge[std::size_t(v.idx())] = s.mesh->surface.point(v)[0] > 0.7;
  const BeltSmoothResult result = smoothBelt(s.mesh->surface, nearEdge, {.rings = 4});
  for (auto v : s.mesh->surface.vertices())
    if (s.mesh->surface.is_boundary(v)) {
      EXPECT_EQ(result.mesh.point(v), s.mesh->surface.point(v));
    }
  EXPECT_TRUE(test::bitIdentical(smoothBelt(s.mesh->surface, s.inside, {.iterations = 0}).mesh,
                                 s.mesh->surface));
  EXPECT_THROW(smoothBelt(s.mesh->surface, {1, 0}, {}), std::invalid_argument);
  EXPECT_THROW(smoothBelt(s.mesh->surface, s.inside, {.rings = 0}), std::out_of_range);
}

// The node on a real mesh with a region raised along its normals: a manifold result with the
// same structure, the paste map metrics reads, nothing moved off the belt and the region.
TEST(BeltSmoothNode, SmoothsTheBeltOfARegionOfARealMesh) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const TriMesh& mesh = bunny->surface;
  const auto origin = mesh.point(TriMesh::VertexHandle(0));
  const double radius = 0.1 * boundingDiagonal(mesh);
  auto sampled = std::make_shared<VertexFields>(mesh);
  std::vector<double> region(mesh.n_vertices(), 0.0), nearest(mesh.n_vertices(), -1.0);
  TriMesh raised = mesh;
  for (auto v : mesh.vertices())
    if ((mesh.point(v) - origin).norm() < radius) {
      region[std::size_t(v.idx())] = 1.0;
      nearest[std::size_t(v.idx())] = v.idx();
      const Eigen::Vector3d n = 0.01 * radius * areaWeightedNormal(mesh, v.idx());
      raised.set_point(v, mesh.point(v) + toPoint(n));
    }
  sampled->add("region", region);
  sampled->add("nearest", nearest);
  const test::NodeRun run = test::runNode(
      "geobrush.belt_smooth",
      {{"mesh", std::make_shared<const Mesh>(raised)}, {"target", bunny}, {"sampled", sampled}});
  const auto result = run.get<Mesh>("mesh");
  const auto map = run.get<PasteMap>("map");
  ASSERT_TRUE(result && map);
  EXPECT_EQ(test::faceIndices(result->surface), test::faceIndices(mesh));
  EXPECT_EQ(map->targetVertex.size(), mesh.n_vertices());
  EXPECT_EQ(map->targetVertex[5], 5);
  for (std::size_t v = 0; v < region.size(); ++v)
    EXPECT_EQ(map->sourceVertex[v], int(nearest[v]));
  EXPECT_FALSE(map->seamFaces.empty());
}

TEST(BeltSmoothNode, RefusesAMeshThatIsNotTheTarget) {
  const MeshPtr grid = test::heightGrid(3, [](double, double) { return 0.0; });
  const MeshPtr other = test::heightGrid(4, [](double, double) { return 0.0; });
  auto sampled = std::make_shared<VertexFields>(grid->surface);
  sampled->add("region", std::vector<double>(16, 1.0));
  sampled->add("nearest", std::vector<double>(16, 0.0));
  try {
    test::runNode("geobrush.belt_smooth",
                  {{"mesh", other}, {"target", grid}, {"sampled", sampled}});
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'mesh'");
  }
}

// Edit after edit (the rebuilt mesh raised by a growing step, then one with another connectivity
// but the same counts), each result retired into a bin for the next: every result and map is a
// fresh node's, bit for bit, and the results nothing holds are recycled.
TEST(BeltSmoothNode, EditAfterEditGivesWhatAFreshNodeGives) {
  const NodeType* type = test::registry().find("geobrush.belt_smooth");
  ASSERT_NE(type, nullptr);
  const Step flat = raisedSquare(16, 0.0);
  auto sampled = std::make_shared<VertexFields>(flat.mesh->surface);
  std::vector<double> region(flat.inside.begin(), flat.inside.end()), nearest(region.size());
  for (std::size_t v = 0; v < nearest.size(); ++v)
    nearest[v] = region[v] != 0.0 ? double(v % 7) : -1.0;
  sampled->add("region", region);
  sampled->add("nearest", nearest);
  const auto node = type->create();
  const auto bin = std::make_shared<RecycleBin>();
  std::set<const Mesh*> made;
  constexpr int kFlipped = 4;
  for (int edit = 0; edit < 6; ++edit) {
    SCOPED_TRACE(edit);
    MeshPtr rebuilt = raisedSquare(16, 0.02 * (edit + 1)).mesh;
    if (edit == kFlipped)
      rebuilt = std::make_shared<const Mesh>(test::withAnEdgeFlipped(rebuilt->surface));
    const std::map<std::string, ValuePtr, std::less<>> inputs = {
        {"mesh", rebuilt}, {"target", flat.mesh}, {"sampled", sampled}};
    test::DirectContext ctx(*type, inputs, {}, nullptr, bin);
    test::run(*node, ctx);
    const auto mesh = std::dynamic_pointer_cast<const Mesh>(ctx.outputs.at("mesh"));
    const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs.at("map"));
    ASSERT_TRUE(mesh && map);
    made.insert(mesh.get());
    const test::NodeRun fresh = test::runNode("geobrush.belt_smooth", inputs);
    EXPECT_TRUE(test::bitIdentical(mesh->surface, fresh.get<Mesh>("mesh")->surface));
    EXPECT_EQ(map->targetVertex, fresh.get<PasteMap>("map")->targetVertex);
    EXPECT_EQ(map->sourceVertex, fresh.get<PasteMap>("map")->sourceVertex);
    EXPECT_EQ(map->seamFaces, fresh.get<PasteMap>("map")->seamFaces);
  }
  EXPECT_LT(made.size(), 6u);
}

}  // namespace
}  // namespace geobrush
