// geobrush.cage_build: the shell cage encloses the canvas, is closed,
// outward and free of self-intersections, on analytic canvases and real ones;
// the fast enclosure test agrees with the winding number.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "cage_build.hpp"
#include "canvas_fixtures.hpp"
#include "geobrush/exponential_map.hpp"
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

// Both meshes in one, the second's vertices renumbered after the first's.
TriMesh merged(const TriMesh& a, const TriMesh& b) {
  TriMesh result = a;
  const int offset = int(a.n_vertices());
  for (auto v : b.vertices())
    result.add_vertex(b.point(v));
  for (auto f : b.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v : b.fv_range(f))
      corners.emplace_back(v.idx() + offset);
    result.add_face(corners);
  }
  return result;
}

TriMesh transformed(TriMesh mesh, const Eigen::Affine3d& transform) {
  for (auto v : mesh.vertices()) {
    const Vector3d p = transform * toEigen(mesh.point(v));
    mesh.point(v) = toPoint(p);
  }
  return mesh;
}

// The fast test must answer as the winding number does; where it trusts its
// crossing count, that count must be the (integer) winding number.
void expectSameAsWindingNumber(const TriMesh& mesh, const EnclosureTest& enclosure,
                               const Vector3d& point) {
  const double reference = windingNumber(mesh, point);
  EXPECT_EQ(enclosure.encloses(point), reference >= 0.5) << point.transpose();
  if (const auto crossings = enclosure.crossingWindingNumber(point)) {
    EXPECT_NEAR(*crossings, reference, 1e-6) << point.transpose();
  }
}

// The armadillo's ear, as graphs/preprocess_armadillo_ear.json paints it: a
// small canvas over a thin, folded feature, so its columns are tall and few
// canvas vertices fall into each cell.
std::shared_ptr<Parameterization> armadilloEar() {
  const MeshPtr armadillo = readMesh(test::meshPath("armadillo.obj")).mesh;
  const TriMesh& m = armadillo->surface;
  const Vector3d earPoint(0.1, 0.37, 0.17);
  int nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (auto f : m.faces()) {
    Vector3d centroid = Vector3d::Zero();
    for (auto v : m.fv_range(f))
      centroid += toEigen(m.point(v)) / 3;
    if ((centroid - earPoint).norm() < best) {
      best = (centroid - earPoint).norm();
      nearest = f.idx();
    }
  }
  auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(armadillo, nearest, 0.1));
  DemResult dem = discreteExponentialMap(*canvas, DemOptions{});
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  param->uv = std::move(dem.uv);
  param->normal = std::move(dem.normal);
  param->origin = dem.origin;
  return param;
}

}  // namespace

TEST(WindingNumber, InsideOutsideOfATetrahedron) {
  const Mesh tet = test::tetrahedron({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  EXPECT_NEAR(windingNumber(tet.surface, {0.1, 0.1, 0.1}), 1.0, 1e-12);
  EXPECT_NEAR(windingNumber(tet.surface, {1, 1, 1}), 0.0, 1e-12);
  EXPECT_NEAR(windingNumber(tet.surface, {-0.2, 0.1, 0.1}), 0.0, 1e-12);
}

TEST(EnclosureTest, UnitCubeAnswersAnalytically) {
  const Eigen::Affine3d tilted(Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));
  int grazing = 0;  // off the surface, yet on rays along its edges (the upright cube's)
  for (const auto& transform : {Eigen::Affine3d::Identity(), tilted}) {
    // Two cells a side: the rays of lattice points graze faces, edges and
    // vertices, where the crossing count is ambiguous.
    const TriMesh cube =
        transformed(test::boxCage(Vector3d::Zero(), Vector3d::Ones(), 2), transform);
    const EnclosureTest enclosure(cube);
    const double steps[] = {-0.5, 0.0, 0.25, 0.5, 0.75, 1.0, 1.5};
    int onSurface = 0;
    for (double x : steps)
      for (double y : steps)
        for (double z : steps) {
          const Vector3d local(x, y, z);
          const Vector3d point = transform * local;
          const bool inside = (local.array() > 0).all() && (local.array() < 1).all();
          const bool outside = (local.array() < 0).any() || (local.array() > 1).any();
          if (inside || outside) {
            EXPECT_EQ(enclosure.encloses(point), inside) << local.transpose();
            if (const auto crossings = enclosure.crossingWindingNumber(point)) {
              EXPECT_EQ(*crossings, inside ? 1 : 0) << local.transpose();
            } else {
              ++grazing;
            }
          } else {
            // On a face, edge or vertex: only the winding number can say.
            ++onSurface;
            EXPECT_FALSE(enclosure.crossingWindingNumber(point)) << local.transpose();
            EXPECT_EQ(enclosure.encloses(point), windingNumber(cube, point) >= 0.5);
          }
        }
    EXPECT_EQ(onSurface, 5 * 5 * 5 - 3 * 3 * 3);  // in the closed cube but not inside
  }
  EXPECT_GT(grazing, 0);
}

TEST(EnclosureTest, OverlappingShellsCountTwice) {
  const TriMesh shells = merged(test::boxCage(Vector3d::Zero(), Vector3d::Ones(), 1),
                                test::boxCage(Vector3d::Constant(0.5), Vector3d::Constant(2), 1));
  const EnclosureTest enclosure(shells);
  EXPECT_EQ(enclosure.crossingWindingNumber({0.7, 0.8, 0.9}), 2);
  EXPECT_EQ(enclosure.crossingWindingNumber({0.2, 0.3, 0.4}), 1);
  EXPECT_EQ(enclosure.crossingWindingNumber({1.7, 1.6, 1.8}), 1);
  EXPECT_EQ(enclosure.crossingWindingNumber({1.7, 0.2, 0.3}), 0);
  EXPECT_NEAR(windingNumber(shells, {0.7, 0.8, 0.9}), 2.0, 1e-12);
}

TEST(EnclosureTest, NeedsAClosedMesh) {
  TriMesh triangle;
  triangle.add_face(triangle.add_vertex({0, 0, 0}), triangle.add_vertex({1, 0, 0}),
                    triangle.add_vertex({0, 1, 0}));
  EXPECT_THROW(EnclosureTest{triangle}, std::invalid_argument);
  const TriMesh nothing;
  EXPECT_FALSE(EnclosureTest(nothing).encloses(Vector3d::Zero()));
}

TEST(EnclosureTest, AgreesWithTheWindingNumberAroundRealCages) {
  auto bump = test::heightFieldParameterization(
      24, [](double x, double y) { return 0.8 * std::exp(-6 * (x * x + y * y)); });
  for (const auto& param : {bump, armadilloEar()}) {
    const TriMesh cage = buildCage(*param).cage.mesh;
    const EnclosureTest enclosure(cage);
    Eigen::AlignedBox3d box;
    for (auto v : cage.vertices())
      box.extend(toEigen(cage.point(v)));
    const double size = box.diagonal().norm();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0, 1);
    // Anywhere around the cage.
    for (int i = 0; i < 3000; ++i) {
      const Vector3d t(unit(random), unit(random), unit(random));
      const Vector3d point = box.min() - 0.1 * box.sizes() + 1.2 * box.sizes().cwiseProduct(t);
      expectSameAsWindingNumber(cage, enclosure, point);
    }
    // On and near faces, edges and vertices.
    std::uniform_int_distribution<int> anyFace(0, int(cage.n_faces()) - 1);
    const double offsets[] = {0, 1e-13, -1e-13, 1e-10, -1e-10, 1e-7, -1e-7, 1e-3, -1e-3};
    int onSurface = 0, clear = 0, trusted = 0;
    for (int i = 0; i < 300; ++i) {
      const auto face = TriMesh::FaceHandle(anyFace(random));
      std::vector<Vector3d> corners;
      for (auto v : cage.fv_range(face))
        corners.push_back(toEigen(cage.point(v)));
      const Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalized();
      double a = unit(random), b = unit(random);
      if (a + b > 1) std::tie(a, b) = std::pair(1 - a, 1 - b);
      const Vector3d onFace =
          corners[0] + a * (corners[1] - corners[0]) + b * (corners[2] - corners[0]);
      const Vector3d onEdge = corners[0] + a * (corners[1] - corners[0]);
      for (const Vector3d& base : {onFace, onEdge, corners[0]})
        for (double offset : offsets) {
          const Vector3d point = base + offset * size * normal;
          expectSameAsWindingNumber(cage, enclosure, point);
          if (offset == 0) {
            ++onSurface;
            EXPECT_FALSE(enclosure.crossingWindingNumber(point)) << point.transpose();
          } else if (std::abs(offset) >= 1e-7) {  // far beyond the tolerance
            ++clear;
            trusted += enclosure.crossingWindingNumber(point).has_value();
          }
        }
    }
    EXPECT_EQ(onSurface, 900);
    // Points clear of the surface are nearly all settled by their crossings.
    EXPECT_GT(trusted, 0.9 * clear);
  }
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

TEST(SelfIntersections, SweepFindsEveryCrossingPair) {
  // A soup of small triangles, checked pair by pair on its own.
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0, 1);
  TriMesh soup;
  std::vector<std::array<OpenMesh::Vec3d, 3>> triangles;
  for (int i = 0; i < 80; ++i) {
    const OpenMesh::Vec3d base(unit(random), unit(random), unit(random));
    std::array<OpenMesh::Vec3d, 3> corners;
    for (auto& corner : corners)
      corner = base + 0.2 * OpenMesh::Vec3d(unit(random), unit(random), unit(random));
    triangles.push_back(corners);
    soup.add_face(soup.add_vertex(corners[0]), soup.add_vertex(corners[1]),
                  soup.add_vertex(corners[2]));
  }
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (std::size_t j = i + 1; j < triangles.size(); ++j) {
      TriMesh pair;
      for (const auto& t : {triangles[i], triangles[j]})
        pair.add_face(pair.add_vertex(t[0]), pair.add_vertex(t[1]), pair.add_vertex(t[2]));
      pairs += countSelfIntersections(pair);
    }
  EXPECT_GT(pairs, 0u);
  EXPECT_EQ(countSelfIntersections(soup), pairs);
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

// Column normals that turn faster than the grid resolves (as on small,
// sparse canvases) must not tilt neighbouring tall columns into a fold.
TEST(CageBuild, RapidlyTurningNormalsEncloseAtTheFirstAttempt) {
  for (double frequency : {9.0, 13.0}) {
    auto param = test::heightFieldParameterization(24, [&](double x, double y) {
      return 0.6 * std::cos(2 * x) * std::cos(2 * y) + 0.18 * std::sin(frequency * (x + 1.3 * y));
    });
    for (std::size_t v = 0; v < param->uv.size(); ++v) {
      const Vector2d uv = param->uv[v];
      param->normal[v] =
          Vector3d(0.7 * std::sin(frequency * uv.x()), 0.7 * std::cos(frequency * uv.y()), 1)
              .normalized();
    }
    const CageBuildResult result = buildCage(*param);
    expectValidCage(*param, result);
    EXPECT_EQ(result.attempts, 1) << frequency;
  }
}

TEST(CageBuild, FoldedCanvasOfTheArmadilloEar) {
  auto param = armadilloEar();
  const CageBuildResult result = buildCage(*param);
  expectValidCage(*param, result);
  EXPECT_LE(result.attempts, 3);
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
