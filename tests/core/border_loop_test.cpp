#include <gtest/gtest.h>

#include "geobrush/border_loop.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/point_pairs.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// An n x n grid of unit squares, two triangles each, counterclockwise seen from +z.
TriMesh grid(int n) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> v;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      v.push_back(mesh.add_vertex(TriMesh::Point(x, y, 0)));
  const auto at = [&](int x, int y) { return v[std::size_t(y * (n + 1) + x)]; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
      mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
    }
  return mesh;
}

TEST(BorderLoop, ASquaresBoundaryIsOneLoopInHalfedgeOrder) {
  const TriMesh mesh = grid(3);
  const auto loops = boundaryLoops(mesh);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 12u);
  EXPECT_EQ(loops[0].front(), 0);
  EXPECT_EQ(borderLoopProblem(mesh, loops[0]), "");
  // The boundary halfedges run clockwise seen from +z: from 0 up the left side first.
  EXPECT_EQ(loops[0][1], 4);
  std::vector<int> reversed(loops[0].rbegin(), loops[0].rend());
  EXPECT_NE(borderLoopProblem(mesh, reversed), "");
  EXPECT_NE(borderLoopProblem(mesh, {0, 1}), "");
  EXPECT_NE(borderLoopProblem(mesh, {0, 4, 99}), "");
  EXPECT_NE(borderLoopProblem(mesh, {0, 5, 10}), "");  // 5 is inside
}

TEST(BorderLoop, EveryHoleOfTheBunnyScanIsALoop) {
  const auto mesh = readMesh(test::meshPath("bunny_scan.obj")).mesh;
  const auto loops = boundaryLoops(mesh->surface);
  EXPECT_GE(loops.size(), 2u);
  std::size_t boundaryEdges = 0;
  for (const auto e : mesh->surface.edges())
    boundaryEdges += mesh->surface.is_boundary(e);
  std::size_t inLoops = 0;
  for (const auto& loop : loops) {
    EXPECT_EQ(borderLoopProblem(mesh->surface, loop), "");
    inLoops += loop.size();
  }
  EXPECT_EQ(inLoops, boundaryEdges);
}

TEST(BorderLoop, HashesFollowTheContent) {
  auto mesh = std::make_shared<const Mesh>(grid(2));
  BorderLoop a;
  a.mesh = mesh;
  a.vertex = boundaryLoops(mesh->surface)[0];
  BorderLoop b = a;
  EXPECT_EQ(a.contentHash(), b.contentHash());
  std::rotate(b.vertex.begin(), b.vertex.begin() + 1, b.vertex.end());
  EXPECT_NE(a.contentHash(), b.contentHash());
  PointPairs p, q;
  p.border = {{0, 0, 0}};
  p.templateVertex = {3};
  q = p;
  EXPECT_EQ(p.contentHash(), q.contentHash());
  q.templateVertex = {4};
  EXPECT_NE(p.contentHash(), q.contentHash());
}

}  // namespace
}  // namespace geobrush
