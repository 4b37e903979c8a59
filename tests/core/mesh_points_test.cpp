// Meshes that differ in their points alone.
#include "geobrush/mesh_points.hpp"

#include <gtest/gtest.h>

#include "canvas_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

TEST(MeshPoints, SameConnectivityLooksPastThePointsAlone) {
  const MeshPtr grid = test::heightGrid(6, [](double, double) { return 0.0; });
  TriMesh moved = grid->surface;
  moved.set_point(TriMesh::VertexHandle(7), {0.3, 0.2, 0.9});
  EXPECT_TRUE(sameConnectivity(grid->surface, moved));
  EXPECT_FALSE(sameConnectivity(grid->surface, test::withAnEdgeFlipped(grid->surface)));
  EXPECT_FALSE(sameConnectivity(grid->surface,
                                test::heightGrid(7, [](double, double) { return 0.0; })->surface));
  TriMesh marked = grid->surface;
  marked.status(TriMesh::VertexHandle(3)).set_feature(true);
  EXPECT_FALSE(sameConnectivity(grid->surface, marked));
}

// A real mesh's points copied into a copy of it moved elsewhere give the mesh back.
TEST(MeshPoints, CopyingThePointsOfARealMeshGivesItBack) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  TriMesh copy = bunny->surface;
  for (auto v : copy.vertices())
    copy.set_point(v, copy.point(v) * 2.0 + OpenMesh::Vec3d(1, 0, 0));
  ASSERT_TRUE(sameConnectivity(copy, bunny->surface));
  copyPoints(bunny->surface, copy);
  EXPECT_TRUE(test::bitIdentical(copy, bunny->surface));
}

}  // namespace
}  // namespace geobrush
