// extractSubmesh: faces copied with their vertices renumbered in source order.
#include <gtest/gtest.h>

#include "geobrush/submesh.hpp"
#include "mesh_checks.hpp"

using namespace geobrush;

TEST(Submesh, CopiesFacesAndRenumbersVertices) {
  const Mesh tet = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  // Faces 3 then 1: (1, 2, 3) and (0, 1, 3).
  const Submesh sub = extractSubmesh(tet.surface, {3, 1});
  EXPECT_EQ(sub.unattachedFace, -1);
  EXPECT_EQ(sub.sourceVertex, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(sub.sourceFace, (std::vector<int>{3, 1}));
  ASSERT_EQ(sub.surface.n_faces(), 2u);
  for (int f = 0; f < 2; ++f) {
    auto a = sub.surface.cfv_begin(TriMesh::FaceHandle(f));
    auto b = tet.surface.cfv_begin(TriMesh::FaceHandle(sub.sourceFace[f]));
    for (int k = 0; k < 3; ++k, ++a, ++b)
      EXPECT_EQ(sub.sourceVertex[a->idx()], b->idx());
  }
  const Submesh one = extractSubmesh(tet.surface, {2});
  EXPECT_EQ(one.sourceVertex, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(one.surface.point(TriMesh::VertexHandle(1)),
            tet.surface.point(TriMesh::VertexHandle(2)));
}
