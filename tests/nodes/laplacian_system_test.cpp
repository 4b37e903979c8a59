#include "laplacian_system.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "emd_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// The vertices of `mesh` within `radius` of (x, y) in the xy plane.
std::vector<int> disc(const TriMesh& mesh, double x, double y, double radius) {
  std::vector<int> vertices;
  for (auto v : mesh.vertices())
    if (std::hypot(mesh.point(v)[0] - x, mesh.point(v)[1] - y) < radius)
      vertices.push_back(v.idx());
  return vertices;
}

// Anchored, L's rows are the whole mesh's: L V_Q + C is the full operator on the region. Dropped,
// the region is an open mesh: its rows sum to zero and its border rows differ from the full ones.
TEST(LaplacianSystem, RestrictsTheOperatorToTheRegion) {
  const MeshPtr bump =
      test::heightGrid(10, [](double x, double y) { return std::exp(-4 * (x * x + y * y)); });
  const std::vector<int> region = disc(bump->surface, 0.1, 0, 0.55);
  const Eigen::MatrixX3d full = cotangentLaplacian(bump->surface) * pointMatrix(bump->surface);
  const LaplacianSystem anchored = buildLaplacianSystem(bump, region, {});
  const LaplacianSystem dropped =
      buildLaplacianSystem(bump, region, {.outside = OutsideNeighbours::drop});
  ASSERT_EQ(anchored.vertices, region);
  const Eigen::MatrixX3d rows = anchored.laplacian * anchored.points + anchored.fixedShare;
  for (std::size_t i = 0; i < region.size(); ++i)
    EXPECT_LT((rows.row(Eigen::Index(i)) - full.row(region[i])).norm(), 1e-12) << i;
  EXPECT_EQ(dropped.fixedShare.norm(), 0.0);
  EXPECT_LT((dropped.laplacian * Eigen::VectorXd::Ones(Eigen::Index(region.size())))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  // The border: region vertices with a neighbour outside, where mu is mu_boundary.
  std::vector<std::uint8_t> inside(bump->surface.n_vertices(), 0);
  for (int v : region)
    inside[std::size_t(v)] = 1;
  std::vector<int> border;
  for (std::size_t i = 0; i < region.size(); ++i) {
    bool out = false;
    for (auto w : bump->surface.vv_range(TriMesh::VertexHandle(region[i])))
      out = out || !inside[std::size_t(w.idx())];
    if (out) border.push_back(int(i));
    EXPECT_EQ(dropped.mu[Eigen::Index(i)], out ? 1.0 : 0.1);
  }
  EXPECT_EQ(dropped.boundary, border);
  EXPECT_EQ(anchored.boundary, border);
  // The tangential part: the original's L V + C less its normal component.
  for (std::size_t i = 0; i < region.size(); ++i) {
    const Eigen::Index k = Eigen::Index(i);
    EXPECT_LT(std::abs(anchored.tangential.row(k).dot(anchored.normals.row(k))), 1e-12);
    const Eigen::RowVector3d normalPart =
        full.row(region[i]).dot(anchored.normals.row(k)) * anchored.normals.row(k);
    EXPECT_LT((anchored.tangential.row(k) + normalPart - full.row(region[i])).norm(), 1e-12);
  }
  EXPECT_FALSE(border.empty());
}

// The factor solves the system of its form: with the original's own L V as the target, V comes
// back.
TEST(LaplacianSystem, FactorsEitherForm) {
  const MeshPtr bump =
      test::heightGrid(8, [](double x, double y) { return 0.3 * std::sin(3 * x) * y; });
  const std::vector<int> region = disc(bump->surface, 0, 0, 0.6);
  const LaplacianSystem screened = buildLaplacianSystem(bump, region, {});
  EXPECT_EQ(screened.form, LaplacianForm::screened);
  const Eigen::MatrixX3d screenedRhs =
      screened.laplacian * screened.points + screened.mu.asDiagonal() * screened.points;
  EXPECT_LT((screened.factor->solve(screenedRhs) - screened.points).norm(), 1e-10);

  const LaplacianSystem squares =
      buildLaplacianSystem(bump, region, {.form = LaplacianForm::leastSquares});
  const Eigen::VectorXd pull = squares.mu.cwiseProduct(squares.mu);
  const Eigen::MatrixX3d rhs =
      squares.laplacian.transpose() * (squares.laplacian * squares.points) +
      pull.asDiagonal() * squares.points;
  EXPECT_LT((squares.factor->solve(rhs) - squares.points).norm(), 1e-10);
  EXPECT_NE(squares.key, screened.key);
}

TEST(LaplacianSystem, KeysOnTheRegionItsGeometryAndMu) {
  const MeshPtr grid = test::heightGrid(6, [](double, double) { return 0.0; });
  const std::vector<int> region = disc(grid->surface, 0, 0, 0.5);
  const Hash key = buildLaplacianSystem(grid, region, {}).key;
  EXPECT_EQ(buildLaplacianSystem(grid, region, {}).key, key);
  EXPECT_NE(buildLaplacianSystem(grid, region, {.mu = 0.2}).key, key);
  EXPECT_NE(buildLaplacianSystem(grid, disc(grid->surface, 0, 0, 0.7), {}).key, key);
  TriMesh moved = grid->surface;
  moved.set_point(TriMesh::VertexHandle(region[0]), {0, 0, 0.1});
  EXPECT_NE(buildLaplacianSystem(std::make_shared<const Mesh>(moved), region, {}).key, key);
}

// A system that reads the whole mesh's differentials (as a dab does) is the one built from the
// region's own faces, bit for bit: anchored or dropped, in either form, on a bump and a real mesh.
TEST(LaplacianSystem, TheWholeMeshsDifferentialsGiveTheSameSystem) {
  const MeshPtr bump =
      test::heightGrid(10, [](double x, double y) { return std::exp(-4 * (x * x + y * y)); });
  const test::RealMeshRegion bunny = test::bunnyRegion();
  const std::pair<MeshPtr, std::vector<int>> cases[] = {{bump, disc(bump->surface, 0.1, 0, 0.55)},
                                                        {bunny.mesh, bunny.system->vertices}};
  for (const auto& [mesh, region] : cases) {
    const MeshDifferentials whole = meshDifferentials(mesh->surface);
    for (const OutsideNeighbours outside : {OutsideNeighbours::anchor, OutsideNeighbours::drop})
      for (const LaplacianForm form : {LaplacianForm::screened, LaplacianForm::leastSquares}) {
        const LaplacianSystemOptions options{.outside = outside, .form = form};
        const LaplacianSystem own = buildLaplacianSystem(mesh, region, options);
        const LaplacianSystem read = buildLaplacianSystem(mesh, region, options, 0, &whole);
        ASSERT_EQ(read.laplacian.nonZeros(), own.laplacian.nonZeros());
        for (int col = 0; col < own.laplacian.outerSize(); ++col)
          for (LaplacianSystem::Sparse::InnerIterator it(own.laplacian, col); it; ++it)
            ASSERT_EQ(read.laplacian.coeff(it.row(), col), it.value());
        EXPECT_EQ(read.fixedShare, own.fixedShare);
        EXPECT_EQ(read.tangential, own.tangential);
        EXPECT_EQ(read.normals, own.normals);
        EXPECT_EQ(read.points, own.points);
        EXPECT_EQ(read.area, own.area);
        EXPECT_EQ(read.mu, own.mu);
        EXPECT_EQ(read.boundary, own.boundary);
        EXPECT_EQ(read.key, own.key);
        const Eigen::MatrixX3d rhs = own.tangential + own.points;
        EXPECT_EQ(read.factor->solve(rhs), own.factor->solve(rhs));
      }
    const MeshDifferentials other = meshDifferentials(bump->surface);
    if (mesh != bump) {
      EXPECT_THROW(buildLaplacianSystem(mesh, region, {}, 0, &other), std::invalid_argument);
    }
  }
}

TEST(LaplacianSystem, RefusesAnEmptyOrUnorderedRegionAndBadMu) {
  const MeshPtr grid = test::heightGrid(4, [](double, double) { return 0.0; });
  EXPECT_THROW(buildLaplacianSystem(grid, {}, {}), std::invalid_argument);
  EXPECT_THROW(buildLaplacianSystem(grid, {3, 2}, {}), std::invalid_argument);
  EXPECT_THROW(buildLaplacianSystem(grid, {2, 99}, {}), std::invalid_argument);
  EXPECT_THROW(buildLaplacianSystem(grid, {2, 3}, {.mu = 0}), std::out_of_range);
}

// The node over a region of a real mesh: the unknowns are the region's mesh vertices.
TEST(LaplacianSystemNode, BuildsTheSystemOfARegionOfARealMesh) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto param = test::projectedParameterization(bunny, Vector3d::UnitX(), Vector3d::UnitY());
  const Vector2d centre = param->uv[0];
  const double radius = 0.1 * boundingDiagonal(bunny->surface);
  const auto region = test::regionWhere(
      *param, *param, [&](const Vector2d& u) { return (u - centre).norm() < radius; });
  const auto system =
      test::runNode("geobrush.laplacian_system", {{"target", param}, {"region", region}})
          .get<LaplacianSystem>("system");
  ASSERT_TRUE(system);
  EXPECT_EQ(system->vertices, region->targetVertices);  // the canvas is the whole mesh
  EXPECT_EQ(system->mesh, bunny);
  EXPECT_FALSE(system->boundary.empty());
  EXPECT_EQ(system->factor->info(), Eigen::Success);

  auto empty = std::make_shared<Region2D>();
  try {
    test::runNode("geobrush.laplacian_system", {{"target", param}, {"region", empty}});
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'region'");
  }
}

}  // namespace
}  // namespace geobrush
