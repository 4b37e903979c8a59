// Snapping points onto a surface: the bounding-volume search against the brute-force one.
#include <gtest/gtest.h>

#include <random>

#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

void expectSameAsBruteForce(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& queries) {
  const SurfaceLocator locator(mesh);
  for (const auto& q : queries) {
    const SurfacePoint expected = nearestSurfacePoint(mesh, q);
    const SurfacePoint found = locator.nearest(q);
    ASSERT_EQ(found.face, expected.face) << q.transpose();
    EXPECT_EQ(found.point, expected.point) << q.transpose();
    EXPECT_EQ(found.distance, expected.distance) << q.transpose();
  }
}

}  // namespace

TEST(SurfaceLocator, FindsTheNearestPointOfACube) {
  const TriMesh cube = test::boxCage(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 3);
  const SurfaceLocator locator(cube);
  // Above the middle of the top face, inside near a side, beyond a corner.
  const SurfacePoint top = locator.nearest({0.4, 0.45, 1.7});
  EXPECT_NEAR(top.distance, 0.7, 1e-15);
  EXPECT_TRUE(top.point.isApprox(Eigen::Vector3d(0.4, 0.45, 1.0), 1e-15));
  const SurfacePoint side = locator.nearest({0.1, 0.5, 0.4});
  EXPECT_NEAR(side.distance, 0.1, 1e-15);
  EXPECT_NEAR(side.point.x(), 0.0, 1e-15);
  const SurfacePoint corner = locator.nearest({2, 2, 2});
  EXPECT_NEAR(corner.distance, std::sqrt(3.0), 1e-15);
  EXPECT_TRUE(corner.point.isApprox(Eigen::Vector3d::Ones(), 1e-15));
}

// Queries on vertices and edges are equally near to several faces: the lowest index wins, as in
// the brute-force search.
TEST(SurfaceLocator, BreaksTiesLikeTheBruteForceSearch) {
  const TriMesh cube = test::boxCage(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 4);
  std::vector<Eigen::Vector3d> queries;
  for (auto v : cube.vertices()) {
    const auto& p = cube.point(v);
    queries.emplace_back(p[0], p[1], p[2]);
    queries.push_back(Eigen::Vector3d(p[0], p[1], p[2]) * 1.5 - Eigen::Vector3d::Constant(0.25));
  }
  for (auto e : cube.edges()) {
    const auto h = cube.halfedge_handle(e, 0);
    const auto a = cube.point(cube.from_vertex_handle(h)), b = cube.point(cube.to_vertex_handle(h));
    queries.emplace_back(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]));
  }
  expectSameAsBruteForce(cube, queries);
}

TEST(SurfaceLocator, AgreesWithTheBruteForceSearchOnARealMesh) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < 300; ++i)
    queries.emplace_back(u(rng), u(rng), u(rng));
  for (auto v : bunny->surface.vertices())
    if (v.idx() % 50 == 0) {
      const auto& p = bunny->surface.point(v);
      queries.emplace_back(p[0], p[1], p[2]);
    }
  expectSameAsBruteForce(bunny->surface, queries);
}

TEST(SurfaceLocator, RefusesAMeshWithoutFaces) {
  EXPECT_THROW(SurfaceLocator{TriMesh()}, std::invalid_argument);
}
