#include "geobrush/laplacian.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/derived_store.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

bool onBorder(const TriMesh& mesh, int v) {
  return mesh.is_boundary(TriMesh::VertexHandle(v));
}

// Cotangent weights reproduce linear functions: L x = 0 away from the border of a flat grid,
// however the grid lies in space.
TEST(CotangentLaplacian, IsZeroOnLinearFunctionsOfAPlaneAndSymmetricWithZeroRows) {
  const Eigen::Isometry3d rigid =
      Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 1, 0).normalized());
  const MeshPtr grid = test::heightGrid(
      12, [](double, double) { return 0.0; }, rigid);
  const TriMesh& mesh = grid->surface;
  const Eigen::SparseMatrix<double> laplacian = cotangentLaplacian(mesh);
  EXPECT_LT((Eigen::SparseMatrix<double>(laplacian.transpose()) - laplacian).norm(), 1e-12);
  const Eigen::VectorXd rowSums = laplacian * Eigen::VectorXd::Ones(laplacian.cols());
  EXPECT_LT(rowSums.cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::MatrixX3d moved = laplacian * pointMatrix(mesh);
  for (int v = 0; v < int(mesh.n_vertices()); ++v)
    if (!onBorder(mesh, v)) {
      EXPECT_LT(moved.row(v).norm(), 1e-12) << v;
    }
}

// On a sphere of radius R the umbrella sum (cot a + cot b)(v_j - v_i) is 2 A_i times the
// Laplace-Beltrami operator of the position, -2 n / R: -4 A_i n / R.
TEST(CotangentLaplacian, GivesFourAreasOverRadiusAlongTheNormalOnASphere) {
  const double radius = 2.5;
  TriMesh sphere = test::icosphere(4);
  for (auto v : sphere.vertices())
    sphere.set_point(v, sphere.point(v) * radius);
  const Eigen::MatrixX3d delta = -(cotangentLaplacian(sphere) * pointMatrix(sphere));
  const Eigen::VectorXd areas = vertexAreas(sphere);
  const auto normals = areaWeightedNormals(sphere);
  EXPECT_NEAR(areas.sum(), test::surfaceArea(sphere), 1e-12 * areas.sum());
  for (auto v : sphere.vertices()) {
    const int i = v.idx();
    const Eigen::Vector3d outward =
        Eigen::Vector3d(sphere.point(v)[0], sphere.point(v)[1], sphere.point(v)[2]).normalized();
    EXPECT_GT(normals[i].dot(outward), 0.999) << i;
    EXPECT_NEAR(delta.row(i).dot(normals[i]), -4 * areas[i] / radius, 0.05 * 4 * areas[i] / radius)
        << i;
  }
}

TEST(VertexFields, KeepColumnsInOrderAndRefuseWhatDoesNotFit) {
  const MeshPtr grid = test::heightGrid(2, [](double, double) { return 0.0; });
  VertexFields fields(grid->surface);
  EXPECT_EQ(fields.vertexCount, 9u);
  fields.add("g", std::vector<double>(9, 1.0));
  fields.add("area", std::vector<double>(9, 2.0));
  EXPECT_EQ(fields.names(), (std::vector<std::string>{"g", "area"}));
  EXPECT_EQ(fields.column("area")[3], 2.0);
  EXPECT_EQ(fields.find("h1"), nullptr);
  EXPECT_THROW(fields.add("g", std::vector<double>(9)), std::invalid_argument);
  EXPECT_THROW(fields.add("h1", std::vector<double>(8)), std::invalid_argument);
  EXPECT_THROW(fields.add("", std::vector<double>(9)), std::invalid_argument);
  try {
    fields.column("h1");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_TRUE(test::contains(e.what(), "no field named 'h1' (there are: g, area)"));
  }
  const Hash before = fields.contentHash();
  fields.columns[0].second[4] = 1.5;
  EXPECT_NE(fields.contentHash(), before);
}

TEST(VertexFields, BelongToTheirMeshWhateverItsColours) {
  const MeshPtr grid = test::heightGrid(3, [](double x, double) { return x; });
  const VertexFields fields(grid->surface);
  EXPECT_EQ(fields.mismatch(grid->surface), "");
  const Mesh coloured(grid->surface, std::vector<Rgb>(grid->surface.n_vertices(), {1, 0, 0}));
  EXPECT_EQ(fields.mismatch(coloured.surface), "");
  EXPECT_NE(geometryHash(coloured.surface), 0u);

  TriMesh moved = grid->surface;
  moved.set_point(TriMesh::VertexHandle(5), moved.point(TriMesh::VertexHandle(5)) * 1.5);
  EXPECT_TRUE(test::contains(fields.mismatch(moved), "another mesh with the same vertex count"));
  const MeshPtr other = test::heightGrid(4, [](double, double) { return 0.0; });
  EXPECT_TRUE(test::contains(fields.mismatch(other->surface),
                             "computed on a mesh of 16 vertices, this one has 25"));
}

// Fields made from a count and a hash, and checked against a hash the caller has, say what the
// mesh's own do; the hash as derived data is computed once per mesh value.
TEST(VertexFields, TakeTheMeshHashFromTheCaller) {
  const MeshPtr grid = test::heightGrid(3, [](double x, double) { return x; });
  const VertexFields fields(grid->surface.n_vertices(), geometryHash(grid->surface));
  EXPECT_EQ(fields.meshHash, VertexFields(grid->surface).meshHash);
  EXPECT_EQ(fields.mismatch(grid->surface, geometryHash(grid->surface)), "");
  EXPECT_TRUE(test::contains(fields.mismatch(grid->surface, geometryHash(grid->surface) + 1),
                             "another mesh with the same vertex count"));
  const MeshPtr other = test::heightGrid(4, [](double, double) { return 0.0; });
  EXPECT_TRUE(test::contains(fields.mismatch(other->surface, fields.meshHash),
                             "computed on a mesh of 16 vertices, this one has 25"));

  const NodeType reader = NodeTypeBuilder("test.reader", 1)
                              .input<Mesh>("mesh", "Any mesh.")
                              .compute([](Context&) {})
                              .build();
  auto store = std::make_shared<DerivedStore>();
  for (int run = 0; run < 2; ++run) {
    test::DirectContext ctx(reader, {{"mesh", grid}}, {}, store);
    EXPECT_EQ(derivedGeometryHash(ctx, grid), fields.meshHash);
  }
  test::DirectContext ctx(reader, {{"mesh", other}}, {}, store);
  EXPECT_EQ(derivedGeometryHash(ctx, other), geometryHash(other->surface));
  EXPECT_EQ(store->builds(), 2u);
}

// On the vertices its faces touch, numbered in mesh order, the operator holds the whole-mesh
// operator's entries bit for bit: a patch costs its own size.
TEST(CotangentLaplacian, OnThePatchItsFacesTouchIsTheWholeOperatorsBlock) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const TriMesh& mesh = bunny->surface;
  std::vector<int> faces;
  for (auto f : mesh.faces())
    if (f.idx() % 3 != 0 && mesh.point(f.halfedge().to())[1] > 0.1) faces.push_back(f.idx());
  ASSERT_FALSE(faces.empty());
  std::vector<int> index(mesh.n_vertices(), -1), touched;
  for (int f : faces)
    for (auto c : mesh.fv_range(TriMesh::FaceHandle(f)))
      index[std::size_t(c.idx())] = 0;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = int(touched.size());
      touched.push_back(int(v));
    }
  const Eigen::SparseMatrix<double> whole = cotangentLaplacian(mesh, faces);
  const Eigen::SparseMatrix<double> patch =
      cotangentLaplacian(mesh, faces, index, int(touched.size()));
  ASSERT_EQ(patch.rows(), Eigen::Index(touched.size()));
  EXPECT_EQ(patch.nonZeros(), whole.nonZeros());
  for (int col = 0; col < patch.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(patch, col); it; ++it)
      ASSERT_EQ(it.value(), whole.coeff(touched[std::size_t(it.row())], touched[std::size_t(col)]));
}

// A real mesh: the areas sum to its surface area and the normals are unit.
TEST(CotangentLaplacian, QuantitiesOfARealMeshAreConsistent) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const TriMesh& mesh = bunny->surface;
  const Eigen::VectorXd areas = vertexAreas(mesh);
  EXPECT_NEAR(areas.sum(), test::surfaceArea(mesh), 1e-12 * areas.sum());
  for (const auto& normal : areaWeightedNormals(mesh))
    EXPECT_NEAR(normal.norm(), 1.0, 1e-12);
  const Eigen::SparseMatrix<double> laplacian = cotangentLaplacian(mesh);
  EXPECT_LT((laplacian * Eigen::VectorXd::Ones(laplacian.cols())).cwiseAbs().maxCoeff(), 1e-9);
}

// One pass over a vertex's faces gives what the three functions give, bit for bit, on a sphere
// (where g = -4 A / R) and on a real mesh with its boundary and obtuse corners.
TEST(CotangentLaplacian, VertexGeometryIsTheThreeQuantitiesInOnePass) {
  const double radius = 2.5;
  TriMesh sphere = test::icosphere(3);
  for (auto v : sphere.vertices())
    sphere.set_point(v, sphere.point(v) * radius);
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const TriMesh* sphereMesh = &sphere;
  for (const TriMesh* mesh : {sphereMesh, &bunny->surface})
    for (auto v : mesh->vertices()) {
      const VertexGeometry geometry = vertexGeometry(*mesh, v.idx());
      ASSERT_EQ(geometry.laplace, cotangentLaplace(*mesh, v.idx())) << v.idx();
      ASSERT_EQ(geometry.normal, areaWeightedNormal(*mesh, v.idx())) << v.idx();
      ASSERT_EQ(geometry.area, vertexArea(*mesh, v.idx())) << v.idx();
      if (mesh == sphereMesh) {
        EXPECT_NEAR(geometry.laplace.dot(geometry.normal), -4 * geometry.area / radius,
                    0.05 * 4 * geometry.area / radius);
      }
    }
}

// The whole mesh's differentials are what cotangentLaplacian, areaWeightedNormals and vertexAreas
// give, bit for bit, on a sphere (radial normals, areas summing to 4 pi R^2) and on a real mesh
// with its boundary; as derived data they are computed once per mesh value.
TEST(MeshDifferentials, AreTheWholeMeshsOperatorNormalsAndAreasOncePerMesh) {
  const double radius = 2.5;
  TriMesh sphere = test::icosphere(3);
  for (auto v : sphere.vertices())
    sphere.set_point(v, sphere.point(v) * radius);
  const MeshPtr sphereMesh = std::make_shared<const Mesh>(std::move(sphere));
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  for (const MeshPtr& mesh : {sphereMesh, bunny}) {
    const MeshDifferentials differentials = meshDifferentials(mesh->surface);
    const Eigen::SparseMatrix<double> laplacian = cotangentLaplacian(mesh->surface);
    ASSERT_EQ(differentials.laplacian.nonZeros(), laplacian.nonZeros());
    for (int col = 0; col < laplacian.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, col); it; ++it)
        ASSERT_EQ(differentials.laplacian.coeff(it.row(), col), it.value());
    EXPECT_EQ(differentials.normals, areaWeightedNormals(mesh->surface));
    EXPECT_EQ(differentials.areas, vertexAreas(mesh->surface));
  }
  const MeshDifferentials onSphere = meshDifferentials(sphereMesh->surface);
  EXPECT_NEAR(onSphere.areas.sum(), 4 * M_PI * radius * radius, 0.01 * 4 * M_PI * radius * radius);
  for (auto v : sphereMesh->surface.vertices())
    EXPECT_GT(onSphere.normals[std::size_t(v.idx())].dot(pointOf(sphereMesh->surface, v)) / radius,
              0.999);

  const NodeType reader = NodeTypeBuilder("test.reader", 1)
                              .input<Mesh>("mesh", "Any mesh.")
                              .compute([](Context&) {})
                              .build();
  auto store = std::make_shared<DerivedStore>();
  std::shared_ptr<const MeshDifferentials> first;
  for (int run = 0; run < 2; ++run) {
    test::DirectContext ctx(reader, {{"mesh", bunny}}, {}, store);
    const auto found = derivedMeshDifferentials(ctx, bunny);
    EXPECT_EQ(found->normals.size(), bunny->surface.n_vertices());
    if (first) {
      EXPECT_EQ(found, first);
    }
    first = found;
  }
  EXPECT_EQ(store->builds(), 1u);
}

}  // namespace
}  // namespace geobrush
