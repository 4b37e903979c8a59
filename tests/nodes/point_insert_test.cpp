#include "point_insert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "direct_context.hpp"
#include "geobrush/border_loop.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// A square of side `side` as two triangles: every edge far longer than the spacings tested.
TriMesh bigSquare(double side) {
  TriMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({side, 0, 0}),
             c = mesh.add_vertex({side, side, 0}), d = mesh.add_vertex({0, side, 0});
  mesh.add_face(a, b, c);
  mesh.add_face(a, c, d);
  return mesh;
}

double nearestVertex(const TriMesh& mesh, const Eigen::Vector3d& p, int except = -1) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto v : mesh.vertices())
    if (v.idx() != except) best = std::min(best, (toEigen(mesh.point(v)) - p).norm());
  return best;
}

// U5: every point of every face (sampled on a barycentric grid) within delta of a vertex.
double coverage(const TriMesh& mesh, int samples = 6) {
  double worst = 0;
  for (const auto f : mesh.faces()) {
    std::vector<Eigen::Vector3d> c;
    for (const auto v : mesh.fv_range(f))
      c.push_back(toEigen(mesh.point(v)));
    for (int i = 0; i <= samples; ++i)
      for (int j = 0; i + j <= samples; ++j) {
        const double s = double(i) / samples, t = double(j) / samples;
        worst = std::max(worst, nearestVertex(mesh, c[0] + s * (c[1] - c[0]) + t * (c[2] - c[0])));
      }
  }
  return worst;
}

// U5: no inserted vertex closer than delta / 2 to another.
double closestFromInserted(const TriMesh& mesh, std::size_t original) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t v = original; v < mesh.n_vertices(); ++v)
    closest = std::min(
        closest, nearestVertex(mesh, toEigen(mesh.point(TriMesh::VertexHandle(int(v)))), int(v)));
  return closest;
}

TEST(PointInsert, APlaneIsCoveredToDeltaWithInsertedPointsHalfADeltaApart) {
  const TriMesh square = bigSquare(1.0);
  for (double delta : {0.3, 0.1, 0.05}) {
    SCOPED_TRACE(delta);
    PointInsertOptions options;
    options.deltaMin = delta;
    options.splitBoundary = true;
    const PointInsertResult result = insertPoints(square, options);
    EXPECT_GT(result.inserted, 0u);
    EXPECT_LE(coverage(result.mesh), delta + 1e-12);
    EXPECT_GE(closestFromInserted(result.mesh, 4), delta / 2);
    EXPECT_EQ(result.closestInserted, closestFromInserted(result.mesh, 4));
    const auto topology = test::topology(result.mesh);
    EXPECT_EQ(topology.boundaryLoops, 1u);
    EXPECT_EQ(topology.eulerCharacteristic, 1);
    EXPECT_NEAR(test::surfaceArea(result.mesh), 1.0, 1e-12);  // the points lie on the plane
    for (const auto v : result.mesh.vertices())
      EXPECT_EQ(result.mesh.point(v)[2], 0.0);
  }
}

TEST(PointInsert, TheBoundaryKeepsItsVerticesUnlessAsked) {
  const TriMesh square = bigSquare(1.0);
  PointInsertOptions options;
  options.deltaMin = 0.1;
  const PointInsertResult kept = insertPoints(square, options);
  EXPECT_EQ(boundaryLoops(kept.mesh), std::vector<std::vector<int>>({{0, 3, 2, 1}}));
  for (int v = 0; v < 4; ++v)
    EXPECT_EQ(kept.mesh.point(TriMesh::VertexHandle(v)), square.point(TriMesh::VertexHandle(v)));
  EXPECT_GE(kept.closestInserted, 0.05);
}

// A closed icosahedron: inserted points stay on its faces, the area and closedness stay.
TEST(PointInsert, AClosedMeshStaysClosedWithItsArea) {
  const TriMesh sphere = test::icosphere(0);
  PointInsertOptions options;
  options.deltaMin = 0.2;
  const PointInsertResult result = insertPoints(sphere, options);
  EXPECT_GT(result.inserted, 20u);
  EXPECT_NEAR(test::surfaceArea(result.mesh), test::surfaceArea(sphere), 1e-12);
  EXPECT_EQ(test::topology(result.mesh).boundaryLoops, 0u);
  EXPECT_EQ(test::topology(result.mesh).eulerCharacteristic, 2);
  EXPECT_LE(coverage(result.mesh), 0.2 + 1e-12);
  EXPECT_GE(result.closestInserted, 0.1);
}

TEST(PointInsert, RefusesWhatItCannotDo) {
  PointInsertOptions options;
  EXPECT_THROW(insertPoints(bigSquare(1), options), PointInsertError);  // delta 0
  // A spacing the area alone cannot meet within the limit is refused before any work: the unit
  // square needs at least 1 / (3 sqrt(3) / 2 delta^2) vertices, 3.8e7 at 1e-4.
  options.deltaMin = 1e-4;
  options.maxVertices = 1000;
  try {
    insertPoints(bigSquare(1), options);
    ADD_FAILURE() << "refused nothing";
  } catch (const PointInsertError& e) {
    EXPECT_THAT(e.what(), testing::HasSubstr("would need about 38490018 vertices, more than 1000"));
  }
  // One the estimate allows that still passes the limit is refused as the refinement reaches it.
  options.deltaMin = 0.05;
  options.maxVertices = std::size_t(1 / (3 * std::sqrt(3.0) / 2 * 0.05 * 0.05)) + 1;
  try {
    insertPoints(bigSquare(1), options);
    ADD_FAILURE() << "refused nothing";
  } catch (const PointInsertError& e) {
    EXPECT_THAT(e.what(), testing::HasSubstr("would pass"));
  }
  options.deltaMin = 1e-300;
  EXPECT_THROW(insertPoints(bigSquare(1e10), options), PointInsertError);
  EXPECT_THROW(borderSpacing(bigSquare(1), {}), PointInsertError);
}

// A real patch: the removed forehead of the Nefertiti case, refined to half its border's spacing.
TEST(PointInsert, RefinesARealPatchToHalfItsBorderSpacing) {
  const auto hole = readMesh(test::meshPath("cases/nefertiti_forehead_hole.obj")).mesh;
  const auto patch = readMesh(test::meshPath("cases/nefertiti_forehead_removed_patch.obj")).mesh;
  const auto loops = boundaryLoops(hole->surface);
  ASSERT_EQ(loops.size(), 1u);
  const double spacing = borderSpacing(hole->surface, loops[0]);
  EXPECT_GT(spacing, 0);
  PointInsertOptions options;
  options.deltaMin = spacing / 2;
  const PointInsertResult result = insertPoints(patch->surface, options);
  EXPECT_GT(result.inserted, patch->surface.n_vertices());
  EXPECT_GE(closestFromInserted(result.mesh, patch->surface.n_vertices()), options.deltaMin / 2);
  EXPECT_EQ(boundaryLoops(result.mesh), boundaryLoops(patch->surface));
  EXPECT_EQ(test::topology(result.mesh).nonManifoldVertices, 0u);
}

TEST(PointInsertNode, MeasuresTheBorderWhenDeltaIsZeroAndNamesWhatIsMissing) {
  const NodeType* type = test::registry().find("geobrush.point_insert");
  ASSERT_TRUE(type);
  const auto hole = readMesh(test::meshPath("cases/bunny_small_back_hole.obj")).mesh;
  auto border = std::make_shared<BorderLoop>();
  border->mesh = hole;
  border->vertex = boundaryLoops(hole->surface)[0];
  const auto square = std::make_shared<const Mesh>(bigSquare(1.0));
  test::DirectContext ctx(*type, {{"template", square}, {"border", border}});
  type->create()->compute(ctx);
  const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
  ASSERT_TRUE(report);
  EXPECT_EQ(report->values.at("delta_min"), borderSpacing(hole->surface, border->vertex));
  EXPECT_GT(report->values.at("inserted"), 0);
  EXPECT_GE(report->values.at("closest_inserted_spacing"), 0.5);

  test::DirectContext alone(*type, {{"template", square}});
  try {
    type->create()->compute(alone);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'delta_min'");
  }
}

}  // namespace
}  // namespace geobrush
