// geobrush.cage_build: the shell cage encloses the canvas, is closed,
// outward and free of self-intersections, on analytic canvases and a real one.
#include <gtest/gtest.h>

#include "cage_build.hpp"
#include "canvas_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

using namespace geobrush;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

void expectValidCage(const Parameterization& param, const CageBuildResult& result) {
  const TriMesh& cage = result.cage.mesh;
  const auto stats = meshStats(cage);
  EXPECT_EQ(stats.boundaryLoops, 0u);
  EXPECT_EQ(stats.components, 1u);
  EXPECT_EQ(stats.eulerCharacteristic, 2);  // a closed shell over a disk is a sphere
  EXPECT_GT(test::signedVolume(cage), 0);
  EXPECT_EQ(countSelfIntersections(cage), 0u);
  EXPECT_EQ(result.cage.top.size(), result.cage.domain.size());
  EXPECT_EQ(result.cage.bottom.size(), result.cage.domain.size());
  EXPECT_EQ(result.cage.frames.size(), result.cage.domain.size());
  EXPECT_EQ(cage.n_vertices(), 2 * result.cage.domain.size());
  std::size_t outside = 0;
  for (auto v : param.canvas->surface.vertices()) {
    const auto& p = param.canvas->surface.point(v);
    outside += windingNumber(cage, {p[0], p[1], p[2]}) < 0.5;
  }
  EXPECT_EQ(outside, 0u);
}

}  // namespace

TEST(WindingNumber, InsideOutsideOfATetrahedron) {
  const Mesh tet = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  EXPECT_NEAR(windingNumber(tet.surface, {0.1, 0.1, 0.1}), 1.0, 1e-12);
  EXPECT_NEAR(windingNumber(tet.surface, {1, 1, 1}), 0.0, 1e-12);
  EXPECT_NEAR(windingNumber(tet.surface, {-0.2, 0.1, 0.1}), 0.0, 1e-12);
}

TEST(SelfIntersections, CrossingTrianglesAreFound) {
  TriMesh mesh;
  auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}),
       c = mesh.add_vertex({0, 1, 0});
  auto d = mesh.add_vertex({0.2, 0.2, -1}), e = mesh.add_vertex({0.2, 0.2, 1}),
       f = mesh.add_vertex({0.9, 0.9, 0});
  mesh.add_face(a, b, c);
  mesh.add_face(d, e, f);  // pierces the first triangle
  EXPECT_EQ(countSelfIntersections(mesh), 1u);
  const Mesh tet = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  EXPECT_EQ(countSelfIntersections(tet.surface), 0u);
}

TEST(CageBuild, FlatCanvasGetsAThinSlab) {
  auto param = test::heightFieldParameterization(20, [](double, double) { return 0.0; });
  CageBuildOptions options;
  options.resolution = 8;
  const CageBuildResult result = buildCage(*param, options);
  expectValidCage(*param, result);
  // Over a plane every column has zero extent: the sheets start at +-margin
  // and smoothing only thins the slab a little.
  for (std::size_t d = 0; d < result.cage.domain.size(); ++d) {
    const auto& top = result.cage.mesh.point(TriMesh::VertexHandle(result.cage.top[d]));
    const auto& bottom = result.cage.mesh.point(TriMesh::VertexHandle(result.cage.bottom[d]));
    EXPECT_GT(top[2], 0.5 * result.margin);
    EXPECT_LT(top[2], 1.2 * result.margin);
    EXPECT_LT(bottom[2], -0.5 * result.margin);
    EXPECT_GT(bottom[2], -1.2 * result.margin);
    EXPECT_NEAR(result.cage.frames[d].normal.z(), 1.0, 1e-12);
  }
  EXPECT_EQ(result.attempts, 1);
}

TEST(CageBuild, TallBumpIsEnclosed) {
  auto param = test::heightFieldParameterization(
      40, [](double x, double y) { return 1.5 * std::exp(-8 * (x * x + y * y)); });
  const CageBuildResult result = buildCage(*param);
  expectValidCage(*param, result);
  double highest = -1;
  for (int t : result.cage.top)
    highest = std::max(highest, result.cage.mesh.point(TriMesh::VertexHandle(t))[2]);
  EXPECT_GT(highest, 1.5);
}

TEST(CageBuild, RealTerrain) {
  auto param = test::terrainParameterization();
  CageBuildOptions options;
  options.resolution = 10;
  const CageBuildResult result = buildCage(*param, options);
  expectValidCage(*param, result);
}

TEST(CageBuild, BadParameterizations) {
  auto param = test::heightFieldParameterization(4, [](double, double) { return 0.0; });
  auto shorter = *param;
  shorter.uv.pop_back();
  EXPECT_THROW(buildCage(shorter), CageBuildError);
  auto nan = *param;
  nan.uv[3].x() = std::nan("");
  try {
    buildCage(nan);
    FAIL();
  } catch (const CageBuildError& e) {
    EXPECT_TRUE(test::contains(e.what(), "non-finite value at vertex 3"));
  }
  CageBuildOptions coarse;
  coarse.resolution = 1;
  EXPECT_THROW(buildCage(*param, coarse), CageBuildError);
}

TEST(CageBuild, Deterministic) {
  auto param = test::heightFieldParameterization(
      16, [](double x, double y) { return 0.3 * std::sin(3 * x) * std::cos(2 * y); });
  const auto a = buildCage(*param);
  const auto b = buildCage(*param);
  EXPECT_EQ(a.cage.contentHash(), b.cage.contentHash());
}
