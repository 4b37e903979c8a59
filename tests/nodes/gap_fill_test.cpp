#include "gap_fill.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

int faceAt(const MeshPtr& mesh, const Eigen::Vector3d& p) {
  return nearestSurfacePoint(mesh->surface, p).face;
}

// The feature lifted by `lift` along z: its own copy, with the canvas' connectivity.
TriMesh lifted(const Canvas& feature, double lift) {
  TriMesh out = feature.surface;
  for (auto v : out.vertices())
    out.set_point(v, out.point(v) + TriMesh::Point(0, 0, lift));
  return out;
}

void expectCleanJoin(const GapFillResult& result, const TriMesh& target, const Canvas& region,
                     const Canvas& feature) {
  const auto shape = test::topology(result.mesh);
  EXPECT_EQ(shape.nonManifoldVertices, 0u);
  EXPECT_EQ(shape.components, 1u);
  EXPECT_EQ(shape.boundaryLoops, test::topology(target).boundaryLoops);
  // The gap: one triangle per vertex of either loop.
  EXPECT_EQ(result.map.seamFaces.size(), region.boundary.size() + feature.boundary.size());
  std::vector<int> all(result.mesh.n_faces());
  for (std::size_t f = 0; f < all.size(); ++f)
    all[f] = int(f);
  EXPECT_EQ(selfIntersections(result.mesh, all, 1e-12 * boundingDiagonal(result.mesh)), 0u);
}

TEST(GapFill, ConcentricLoopsOnAPlaneGiveNPlusMTriangles) {
  const MeshPtr plane = test::heightGrid(24, [](double, double) { return 0.0; });
  const int centre = faceAt(plane, {0.01, 0.02, 0});
  const Canvas region = test::growDiscCanvas(plane, centre, 0.7);
  const Canvas feature = test::growDiscCanvas(plane, centre, 0.4);
  const GapFillResult result =
      fillGap(plane->surface, region, lifted(feature, 0.0), feature, GapFillOptions{0});
  expectCleanJoin(result, plane->surface, region, feature);
  // Without smoothing nothing moves: the kept target and the feature are where they were.
  for (auto v : result.mesh.vertices()) {
    const int t = result.map.targetVertex[std::size_t(v.idx())];
    const int s = result.map.sourceVertex[std::size_t(v.idx())];
    ASSERT_NE(t >= 0, s >= 0);
    const auto expected = t >= 0 ? plane->surface.point(TriMesh::VertexHandle(t))
                                 : feature.surface.point(TriMesh::VertexHandle(s));
    EXPECT_EQ(result.mesh.point(v), expected);
  }
}

TEST(GapFill, RingSmoothingKeepsAPlanarGapPlanarAndMovesOnlyNearTheGap) {
  const MeshPtr plane = test::heightGrid(24, [](double, double) { return 0.0; });
  const int centre = faceAt(plane, {0.01, 0.02, 0});
  const Canvas region = test::growDiscCanvas(plane, centre, 0.7);
  const Canvas feature = test::growDiscCanvas(plane, centre, 0.4);
  const GapFillResult result = fillGap(plane->surface, region, feature.surface, feature);
  expectCleanJoin(result, plane->surface, region, feature);
  std::size_t moved = 0;
  for (auto v : result.mesh.vertices()) {
    EXPECT_EQ(result.mesh.point(v)[2], 0.0);
    const int t = result.map.targetVertex[std::size_t(v.idx())];
    if (t >= 0 && result.mesh.point(v) != plane->surface.point(TriMesh::VertexHandle(t))) ++moved;
    // Nothing beyond three rings of the hole moves.
    if (t >= 0 && std::hypot(result.mesh.point(v)[0], result.mesh.point(v)[1]) > 1.0) {
      EXPECT_EQ(result.mesh.point(v), plane->surface.point(TriMesh::VertexHandle(t)));
    }
  }
  EXPECT_GT(moved, region.boundary.size());
}

TEST(GapFill, AFeatureRaisedOverASphereJoinsWithoutFolding) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const double r = boundingDiagonal(sphere->surface) / (2 * std::sqrt(3.0));
  const int top = faceAt(sphere, {0.02 * r, 0.01 * r, r});
  const Canvas region = test::growDiscCanvas(sphere, top, 0.5 * r);
  const Canvas feature = test::growDiscCanvas(sphere, top, 0.3 * r);
  const GapFillResult result = fillGap(sphere->surface, region, lifted(feature, 0.05 * r), feature);
  expectCleanJoin(result, sphere->surface, region, feature);
  EXPECT_EQ(test::topology(result.mesh).eulerCharacteristic, 2);
}

std::vector<Eigen::Vector2d> xy(const TriMesh& mesh) {
  std::vector<Eigen::Vector2d> uv;
  for (auto v : mesh.vertices())
    uv.emplace_back(mesh.point(v)[0], mesh.point(v)[1]);
  return uv;
}

// A wide gap around a feature raised high over the plane: zipped in the domain, no gap triangle
// turns over there, and the join stays clean.
TEST(GapFill, InTheDomainNoGapTriangleTurnsOver) {
  const MeshPtr plane = test::heightGrid(24, [](double, double) { return 0.0; });
  const int centre = faceAt(plane, {0.01, 0.02, 0});
  const Canvas region = test::growDiscCanvas(plane, centre, 0.8);
  const Canvas feature = test::growDiscCanvas(plane, centre, 0.3);
  const std::vector<Eigen::Vector2d> regionUv = xy(region.surface), featureUv = xy(feature.surface);
  const GapFillResult result = fillGap(plane->surface, region, lifted(feature, 0.4), feature,
                                       GapFillOptions{0}, GapDomain{&regionUv, &featureUv});
  expectCleanJoin(result, plane->surface, region, feature);
  for (int f : result.map.seamFaces) {
    std::vector<Eigen::Vector2d> corners;
    for (auto v : result.mesh.fv_range(TriMesh::FaceHandle(f)))
      corners.emplace_back(result.mesh.point(v)[0], result.mesh.point(v)[1]);
    const Eigen::Vector2d e = corners[1] - corners[0], g = corners[2] - corners[0];
    EXPECT_GE(e.x() * g.y() - e.y() * g.x(), 0) << f;
  }
}

TEST(GapFillNode, JoinsAndRefusesAPasteOfAnotherShape) {
  const MeshPtr plane = test::heightGrid(16, [](double, double) { return 0.0; });
  const int centre = faceAt(plane, {0.01, 0.02, 0});
  auto region = std::make_shared<const Canvas>(test::growDiscCanvas(plane, centre, 0.7));
  auto feature = std::make_shared<const Canvas>(test::growDiscCanvas(plane, centre, 0.4));
  const NodeType* type = test::registry().find("geobrush.gap_fill");
  ASSERT_NE(type, nullptr);
  auto pasted = std::make_shared<const Mesh>(feature->surface);
  test::DirectContext ctx(
      *type, {{"target", plane}, {"region", region}, {"pasted", pasted}, {"feature", feature}});
  test::run(type->create(), ctx);
  const auto map = std::dynamic_pointer_cast<const PasteMap>(ctx.outputs.at("map"));
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->seamFaces.size(), region->boundary.size() + feature->boundary.size());

  auto wrong = std::make_shared<const Mesh>(region->surface);
  test::DirectContext bad(
      *type, {{"target", plane}, {"region", region}, {"pasted", wrong}, {"feature", feature}});
  try {
    test::run(type->create(), bad);
    FAIL() << "a paste of another shape was joined";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'pasted'");
    EXPECT_NE(std::string(e.what()).find("connectivity"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace geobrush
