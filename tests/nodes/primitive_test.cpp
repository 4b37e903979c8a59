#include "primitive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Vec3d = OpenMesh::Vec3d;
constexpr double kPi = std::numbers::pi;

PrimitiveOptions options(PrimitiveShape shape, int resolution, double size = 1.0,
                         double minorRadius = 0.25) {
  PrimitiveOptions o;
  o.shape = shape;
  o.resolution = resolution;
  o.size = size;
  o.minorRadius = minorRadius;
  return o;
}

// The exact outward unit normal of the base shape at (or, for points displaced along it, above)
// a point.
Vec3d analyticNormal(const PrimitiveOptions& o, const Vec3d& p) {
  switch (o.shape) {
    case PrimitiveShape::Plane:
      return {0, 0, 1};
    case PrimitiveShape::Sphere:
      return p.normalized();
    case PrimitiveShape::RoundedCube: {
      const double a = o.size - o.minorRadius;
      Vec3d inner;
      for (int i = 0; i < 3; ++i)
        inner[i] = std::clamp(p[i], -a, a);
      return (p - inner).normalized();
    }
    case PrimitiveShape::Torus: {
      const double rho = std::hypot(p[0], p[1]);
      const Vec3d core(o.size * p[0] / rho, o.size * p[1] / rho, 0);
      return (p - core).normalized();
    }
    case PrimitiveShape::Cylinder:
      return Vec3d(p[0], p[1], 0).normalized();
  }
  return {};
}

double roundedBoxDistance(const Vec3d& p, double a) {
  Vec3d inner;
  for (int i = 0; i < 3; ++i)
    inner[i] = std::clamp(p[i], -a, a);
  return (p - inner).norm();
}

// Relative errors of area and volume against the exact values, at each resolution.
struct Errors {
  std::vector<double> area, volume;
};
Errors convergence(PrimitiveOptions o, const std::vector<int>& resolutions, double area,
                   double volume) {
  Errors e;
  for (int n : resolutions) {
    o.resolution = n;
    const TriMesh mesh = makePrimitive(o);
    e.area.push_back(std::abs(test::surfaceArea(mesh) - area) / area);
    e.volume.push_back(std::abs(test::signedVolume(mesh) - volume) / volume);
  }
  return e;
}

// Each doubling of the resolution must shrink the error by at least `factor` (second order
// methods give about 4).
void expectConverges(const std::vector<double>& errors, double factor) {
  for (std::size_t i = 1; i < errors.size(); ++i) {
    EXPECT_LT(errors[i] * factor, errors[i - 1]) << "at step " << i;
  }
}

TEST(Primitive, SphereVerticesLieOnTheSphere) {
  const double r = 1.7;
  const TriMesh mesh = makePrimitive(options(PrimitiveShape::Sphere, 9, r));
  for (auto v : mesh.vertices())
    EXPECT_NEAR(mesh.point(v).norm(), r, 1e-12 * r);
  const auto t = test::topology(mesh);
  EXPECT_EQ(t.faces, 20u * 81);
  EXPECT_EQ(t.eulerCharacteristic, 2);
  EXPECT_EQ(t.boundaryHalfedges, 0u);
  EXPECT_EQ(t.components, 1u);
}

TEST(Primitive, SphereAreaAndVolumeConverge) {
  const double r = 0.8;
  const Errors e = convergence(options(PrimitiveShape::Sphere, 0, r), {4, 8, 16}, 4 * kPi * r * r,
                               4.0 / 3 * kPi * r * r * r);
  expectConverges(e.area, 3.5);
  expectConverges(e.volume, 3.5);
  EXPECT_LT(e.area.back(), 3e-3);
  EXPECT_LT(e.volume.back(), 5e-3);
}

TEST(Primitive, TorusVerticesLieOnTheTube) {
  const double major = 1.5, minor = 0.4;
  const TriMesh mesh = makePrimitive(options(PrimitiveShape::Torus, 40, major, minor));
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    EXPECT_NEAR(std::hypot(std::hypot(p[0], p[1]) - major, p[2]), minor, 1e-12 * major);
  }
  const auto t = test::topology(mesh);
  EXPECT_EQ(t.faces, 2u * 40 * torusTubeSegments(40, major, minor));
  EXPECT_EQ(t.eulerCharacteristic, 0);  // genus 1
  EXPECT_EQ(t.boundaryHalfedges, 0u);
  EXPECT_EQ(t.components, 1u);
}

TEST(Primitive, TorusAreaAndVolumeConverge) {
  const double major = 1.0, minor = 0.3;
  const Errors e =
      convergence(options(PrimitiveShape::Torus, 0, major, minor), {24, 48, 96},
                  4 * kPi * kPi * major * minor, 2 * kPi * kPi * major * minor * minor);
  expectConverges(e.area, 3.5);
  expectConverges(e.volume, 3.5);
  EXPECT_LT(e.volume.back(), 1e-2);
}

// The open tube of radius r and height h around the z axis, facing outward, two boundary loops.
TEST(Primitive, CylinderVerticesLieOnTheTubeBetweenItsRims) {
  const double r = 0.7, h = 2.3;
  PrimitiveOptions o = options(PrimitiveShape::Cylinder, 36, r);
  o.height = h;
  const TriMesh mesh = makePrimitive(o);
  const int rows = cylinderRows(36, r, h);
  EXPECT_EQ(rows, int(std::lround(36 * h / (2 * kPi * r))));
  std::size_t onRims = 0;
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    EXPECT_NEAR(std::hypot(p[0], p[1]), r, 1e-12 * r);
    EXPECT_LE(std::abs(p[2]), h / 2 * (1 + 1e-15));
    if (std::abs(std::abs(p[2]) - h / 2) < 1e-12 * h) ++onRims;
  }
  EXPECT_EQ(onRims, 2u * 36);
  for (auto f : mesh.faces()) {
    const auto n = mesh.calc_face_normal(f);
    const auto c = mesh.calc_face_centroid(f);
    EXPECT_GT(n[0] * c[0] + n[1] * c[1], 0) << f.idx();
    EXPECT_NEAR(n[2], 0, 1e-12);
  }
  const auto t = test::topology(mesh);
  EXPECT_EQ(t.faces, 2u * 36 * std::size_t(rows));
  EXPECT_EQ(t.eulerCharacteristic, 0);  // an annulus
  EXPECT_EQ(t.boundaryLoops, 2u);
  EXPECT_EQ(t.boundaryHalfedges, 2u * 36);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
}

// The polygonal tube's area, 2 n r sin(pi / n) h, tends to 2 pi r h at second order.
TEST(Primitive, CylinderAreaConverges) {
  const double r = 1.2, h = 0.9;
  PrimitiveOptions o = options(PrimitiveShape::Cylinder, 0, r);
  o.height = h;
  const Errors e = convergence(o, {12, 24, 48}, 2 * kPi * r * h, 1.0);
  expectConverges(e.area, 3.5);
  o.resolution = 48;
  EXPECT_NEAR(test::surfaceArea(makePrimitive(o)), 2 * 48 * r * std::sin(kPi / 48) * h, 1e-12);
}

TEST(Primitive, PlaneIsAFlatSquareWithExactArea) {
  const double side = 2.5;
  const int n = 10;
  const TriMesh mesh = makePrimitive(options(PrimitiveShape::Plane, n, side));
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    EXPECT_EQ(p[2], 0.0);
    EXPECT_LE(std::max(std::abs(p[0]), std::abs(p[1])), side / 2);
  }
  EXPECT_NEAR(test::surfaceArea(mesh), side * side, 1e-12 * side * side);
  for (auto f : mesh.faces())
    EXPECT_GT(mesh.calc_face_normal(f)[2], 0.0) << "faces +z";
  const auto t = test::topology(mesh);
  EXPECT_EQ(t.faces, 2u * n * n);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.boundaryHalfedges, 4u * n);
  EXPECT_EQ(t.eulerCharacteristic, 1);  // a disk
  EXPECT_EQ(t.components, 1u);
}

TEST(Primitive, RoundedCubeVerticesLieOnTheRoundedBox) {
  const double half = 1.2, radius = 0.3;
  const TriMesh mesh = makePrimitive(options(PrimitiveShape::RoundedCube, 20, half, radius));
  for (auto v : mesh.vertices()) {
    EXPECT_NEAR(roundedBoxDistance(mesh.point(v), half - radius), radius, 1e-12 * half);
  }
  const auto t = test::topology(mesh);
  EXPECT_EQ(t.faces, 12u * 20 * 20);
  EXPECT_EQ(t.eulerCharacteristic, 2);  // genus 0
  EXPECT_EQ(t.boundaryHalfedges, 0u);
  EXPECT_EQ(t.components, 1u);
}

TEST(Primitive, RoundedCubeAreaAndVolumeConverge) {
  const double half = 1.0, r = 0.4, a = half - r;
  const double area = 24 * a * a + 12 * kPi * a * r + 4 * kPi * r * r;
  const double volume =
      8 * a * a * a + 24 * a * a * r + 6 * kPi * a * r * r + 4.0 / 3 * kPi * r * r * r;
  const Errors e =
      convergence(options(PrimitiveShape::RoundedCube, 0, half, r), {16, 32, 64}, area, volume);
  expectConverges(e.area, 3.5);
  expectConverges(e.volume, 3.5);
  EXPECT_LT(e.volume.back(), 5e-4);
}

TEST(Primitive, RoundedCubeLimitsStayValid) {
  // Edge radius = half-extent: a sphere.
  const TriMesh sphere = makePrimitive(options(PrimitiveShape::RoundedCube, 12, 2.0, 2.0));
  for (auto v : sphere.vertices())
    EXPECT_NEAR(sphere.point(v).norm(), 2.0, 1e-12);
  EXPECT_EQ(test::topology(sphere).eulerCharacteristic, 2);
  // A nearly sharp cube: the volume approaches (2 * half)^3.
  const TriMesh cube = makePrimitive(options(PrimitiveShape::RoundedCube, 12, 1.0, 1e-4));
  EXPECT_EQ(test::topology(cube).eulerCharacteristic, 2);
  EXPECT_EQ(test::topology(cube).nonManifoldVertices, 0u);
  EXPECT_NEAR(test::signedVolume(cube), 8.0, 1e-2);
  EXPECT_GT(test::minAngleDegrees(cube), 1.0);
}

// What every shape must give, with and without relief.
struct ShapeCase {
  PrimitiveShape shape;
  double size, minorRadius;
  int resolution;
  // Smallest face angle of the base shape at this resolution, in degrees.
  double minAngle;
};

class EveryShape : public ::testing::TestWithParam<ShapeCase> {
 protected:
  PrimitiveOptions base() const {
    const ShapeCase& c = GetParam();
    return options(c.shape, c.resolution, c.size, c.minorRadius);
  }
};

TEST_P(EveryShape, IsAWellShapedManifoldFacingOutward) {
  const PrimitiveOptions o = base();
  const TriMesh mesh = makePrimitive(o);
  const auto t = test::topology(mesh);
  const bool plane = o.shape == PrimitiveShape::Plane;
  EXPECT_EQ(t.boundaryLoops, plane ? 1u : 0u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.isolatedVertices, 0u);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.faces, primitiveFaceCount(o));
  if (!plane) {
    EXPECT_GT(test::signedVolume(mesh), 0.0);
  }
  EXPECT_EQ(test::closeVertexPairs(mesh, 1e-6 * o.size), 0u) << "unwelded seam";
  EXPECT_GE(test::minAngleDegrees(mesh), GetParam().minAngle);
  // Every face, not just the total, faces along the exact outward normal.
  std::size_t inward = 0;
  for (auto f : mesh.faces()) {
    const Vec3d centroid = mesh.calc_face_centroid(f);
    if ((mesh.calc_face_normal(f) | analyticNormal(o, centroid)) <= 0) ++inward;
  }
  EXPECT_EQ(inward, 0u);
}

TEST_P(EveryShape, IsDeterministic) {
  PrimitiveOptions o = base();
  o.relief = 0.05 * o.size;
  const TriMesh a = makePrimitive(o);
  const TriMesh b = makePrimitive(o);
  EXPECT_TRUE(test::bitIdentical(a, b));
}

TEST_P(EveryShape, ReliefMovesAlongTheNormalByAtMostTheAmplitude) {
  PrimitiveOptions o = base();
  const TriMesh flat = makePrimitive(o);
  o.relief = 0.1 * std::min(o.size, o.minorRadius);
  o.reliefFrequency = 3;
  const TriMesh bumpy = makePrimitive(o);
  ASSERT_EQ(flat.n_vertices(), bumpy.n_vertices());
  EXPECT_EQ(test::faceIndices(flat), test::faceIndices(bumpy));

  double largest = 0, lowest = 0, highest = 0;
  for (auto v : flat.vertices()) {
    const Vec3d p = flat.point(v);
    const Vec3d d = bumpy.point(v) - p;
    const Vec3d normal = analyticNormal(o, p);
    EXPECT_LE((d % normal).norm(), 1e-12 * o.size) << "displacement off the normal";
    const double height = d | normal;
    EXPECT_LE(std::abs(height), o.relief * (1 + 1e-12));
    largest = std::max(largest, std::abs(height));
    lowest = std::min(lowest, height);
    highest = std::max(highest, height);
  }
  // The relief is really there, both raised and sunk.
  EXPECT_GT(largest, 0.3 * o.relief);
  EXPECT_LT(lowest, -0.05 * o.relief);
  EXPECT_GT(highest, 0.05 * o.relief);

  const auto t = test::topology(bumpy);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  if (o.shape != PrimitiveShape::Plane) {
    EXPECT_GT(test::signedVolume(bumpy), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Primitive, EveryShape,
    ::testing::Values(ShapeCase{PrimitiveShape::Plane, 2.0, 0.25, 16, 44.9},
                      ShapeCase{PrimitiveShape::Sphere, 1.0, 0.25, 12, 50.0},
                      ShapeCase{PrimitiveShape::RoundedCube, 1.0, 0.25, 16, 30.0},
                      ShapeCase{PrimitiveShape::RoundedCube, 1.0, 1.0, 10, 30.0},
                      ShapeCase{PrimitiveShape::Torus, 1.0, 0.25, 48, 30.0},
                      ShapeCase{PrimitiveShape::Torus, 2.0, 1.2, 24, 15.0}),
    [](const auto& info) {
      return std::string(primitiveShapeName(info.param.shape)) + "_" + std::to_string(info.index);
    });

TEST(Primitive, ReliefFrequencyScalesWithSize) {
  // The same shape at twice the size, with twice the amplitude, is the same mesh scaled.
  PrimitiveOptions o = options(PrimitiveShape::Sphere, 6, 1.0);
  o.relief = 0.05;
  const TriMesh small = makePrimitive(o);
  o.size = 2.0;
  o.relief = 0.1;
  const TriMesh large = makePrimitive(o);
  for (auto v : small.vertices()) {
    EXPECT_LE((2.0 * small.point(v) - large.point(v)).norm(), 1e-12);
  }
}

TEST(Primitive, FaceCountsFollowTheResolution) {
  EXPECT_EQ(primitiveFaceCount(options(PrimitiveShape::Plane, 1000)), 2'000'000u);
  EXPECT_EQ(primitiveFaceCount(options(PrimitiveShape::Sphere, 316)), 20u * 316 * 316);
  EXPECT_EQ(primitiveFaceCount(options(PrimitiveShape::RoundedCube, 408)), 12u * 408 * 408);
  EXPECT_EQ(torusTubeSegments(64, 1.0, 0.25), 16);
  EXPECT_EQ(torusTubeSegments(4, 1.0, 0.1), 3);
  EXPECT_EQ(makePrimitive(options(PrimitiveShape::Torus, 3, 1.0, 0.1)).n_faces(), 18u);
  EXPECT_EQ(makePrimitive(options(PrimitiveShape::Sphere, 1)).n_vertices(), 12u);
  EXPECT_EQ(makePrimitive(options(PrimitiveShape::RoundedCube, 1)).n_vertices(), 8u);
}

TEST(Primitive, DefaultsGiveAMediumSphere) {
  const PrimitiveOptions o;
  EXPECT_EQ(o.shape, PrimitiveShape::Sphere);
  const TriMesh mesh = makePrimitive(o);
  EXPECT_EQ(mesh.n_faces(), 20u * 64 * 64);
  EXPECT_NEAR(test::signedVolume(mesh), 4.0 / 3 * kPi, 1e-3);
}

// The option an invalid setting is reported against.
std::string rejectedOption(const PrimitiveOptions& o) {
  try {
    makePrimitive(o);
  } catch (const PrimitiveOptionError& e) {
    return e.option();
  }
  return "(accepted)";
}

TEST(Primitive, RejectsInvalidOptionsNamingTheOption) {
  auto with = [](PrimitiveShape shape, auto change) {
    PrimitiveOptions o = options(shape, 8);
    change(o);
    return rejectedOption(o);
  };
  using S = PrimitiveShape;
  EXPECT_EQ(with(S::Sphere, [](auto& o) { o.size = 0; }), "size");
  EXPECT_EQ(with(S::Plane, [](auto& o) { o.size = std::nan(""); }), "size");
  EXPECT_EQ(with(S::Torus, [](auto& o) { o.minorRadius = 1.0; }), "minor_radius");
  EXPECT_EQ(with(S::Torus, [](auto& o) { o.minorRadius = -0.1; }), "minor_radius");
  EXPECT_EQ(with(S::RoundedCube, [](auto& o) { o.minorRadius = 1.01; }), "minor_radius");
  EXPECT_EQ(with(S::Plane, [](auto& o) { o.resolution = 0; }), "resolution");
  EXPECT_EQ(with(S::Torus, [](auto& o) { o.resolution = 2; }), "resolution");
  EXPECT_EQ(with(S::Sphere, [](auto& o) { o.resolution = 708; }), "resolution");
  EXPECT_EQ(with(S::Sphere, [](auto& o) { o.resolution = 2'000'000'000; }), "resolution");
  EXPECT_EQ(with(S::Plane, [](auto& o) { o.relief = -1; }), "relief");
  EXPECT_EQ(with(S::Sphere, [](auto& o) { o.relief = 1.0; }), "relief");
  EXPECT_EQ(with(S::RoundedCube, [](auto& o) { o.relief = 0.25; }), "relief");
  EXPECT_EQ(with(S::Torus, [](auto& o) { o.relief = 0.3; }), "relief");
  EXPECT_EQ(with(S::Torus,
                 [](auto& o) {
                   o.minorRadius = 0.6;
                   o.relief = 0.45;
                 }),
            "relief");
  EXPECT_EQ(with(S::Plane, [](auto& o) { o.reliefFrequency = 0; }), "relief_frequency");
  EXPECT_EQ(with(S::Cylinder, [](auto& o) { o.height = 0; }), "height");
  EXPECT_EQ(with(S::Cylinder, [](auto& o) { o.resolution = 2; }), "resolution");
  EXPECT_EQ(with(S::Cylinder, [](auto& o) { o.relief = 1.0; }), "relief");
  EXPECT_EQ(with(S::Sphere, [](auto& o) { o.height = -1; }), "(accepted)");
  try {
    makePrimitive(options(S::Sphere, 708));
    ADD_FAILURE() << "a sphere of 10,025,280 faces was made";
  } catch (const PrimitiveOptionError& e) {
    EXPECT_STREQ(e.what(), "gives 10025280 faces for a sphere; at most 10000000 are allowed");
  }
  // Unused settings are not checked: a plane ignores the minor radius.
  EXPECT_EQ(with(S::Plane, [](auto& o) { o.minorRadius = 5; }), "(accepted)");
}

TEST(Primitive, ShapeNamesRoundTrip) {
  ASSERT_EQ(primitiveShapeNames().size(), 5u);
  for (const std::string& name : primitiveShapeNames()) {
    EXPECT_EQ(primitiveShapeName(parsePrimitiveShape(name)), name);
  }
  try {
    parsePrimitiveShape("cone");
    FAIL() << "accepted an unknown shape";
  } catch (const PrimitiveOptionError& e) {
    EXPECT_EQ(e.option(), "shape");
    EXPECT_NE(std::string(e.what()).find("cone"), std::string::npos);
  }
}

TEST(Primitive, ReportsProgressAndCanBeAbandoned) {
  PrimitiveOptions o = options(PrimitiveShape::RoundedCube, 20);
  std::vector<double> reported;
  o.progress = [&](double f) { reported.push_back(f); };
  makePrimitive(o);
  ASSERT_FALSE(reported.empty());
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_GE(reported.front(), 0.0);
  EXPECT_EQ(reported.back(), 1.0);

  struct Stop {};
  o.progress = [](double f) {
    if (f > 0.2) throw Stop{};
  };
  EXPECT_THROW(makePrimitive(o), Stop);
}

// One primitive node evaluated by the real evaluator with the built plugin.
struct NodeRun {
  EvalReport report;
  MeshPtr mesh;
};
NodeRun evaluatePrimitive(ParamMap params) {
  Graph graph;
  graph.nodes["primitive"] = {"geobrush.primitive", 1, std::move(params)};
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  NodeRun run;
  run.report = evaluator.evaluate(graph);
  run.mesh = std::dynamic_pointer_cast<const Mesh>(evaluator.output("primitive", "mesh"));
  return run;
}

TEST(PrimitiveNode, GivesTheAlgorithmsMesh) {
  const NodeRun run = evaluatePrimitive({{"shape", std::string("torus")},
                                         {"size", 2.0},
                                         {"minor_radius", 0.5},
                                         {"resolution", std::int64_t{24}},
                                         {"relief", 0.05},
                                         {"relief_frequency", 2.0}});
  ASSERT_TRUE(run.report.ok) << run.report.error;
  ASSERT_NE(run.mesh, nullptr);
  PrimitiveOptions o = options(PrimitiveShape::Torus, 24, 2.0, 0.5);
  o.relief = 0.05;
  o.reliefFrequency = 2.0;
  EXPECT_TRUE(test::bitIdentical(run.mesh->surface, makePrimitive(o)));
  EXPECT_TRUE(run.mesh->vertexColors.empty());
}

TEST(PrimitiveNode, DefaultsMatchTheAlgorithmsDefaults) {
  const NodeRun run = evaluatePrimitive({});
  ASSERT_TRUE(run.report.ok) << run.report.error;
  ASSERT_NE(run.mesh, nullptr);
  EXPECT_TRUE(test::bitIdentical(run.mesh->surface, makePrimitive({})));
}

TEST(PrimitiveNode, ReportsTheOffendingParam) {
  const NodeRun run = evaluatePrimitive({{"shape", std::string("torus")}, {"minor_radius", 1.5}});
  EXPECT_FALSE(run.report.ok);
  EXPECT_NE(run.report.error.find("param 'minor_radius'"), std::string::npos) << run.report.error;
}

}  // namespace
}  // namespace geobrush
