#include "transform.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

TriMesh readBunny() {
  TriMesh mesh;
  const auto path = test::meshPath("bunny_small.obj");
  if (!OpenMesh::IO::read_mesh(mesh, path.string())) {
    ADD_FAILURE() << "cannot read " << path;
  }
  return mesh;
}

// One triangle per point, so that single points can be pushed through transformMesh.
TriMesh pointsMesh(const std::vector<Eigen::Vector3d>& points) {
  TriMesh mesh;
  for (const auto& p : points) {
    const auto a = mesh.add_vertex(toPoint(p));
    const auto b = mesh.add_vertex({p.x() + 1, p.y(), p.z()});
    const auto c = mesh.add_vertex({p.x(), p.y() + 1, p.z()});
    mesh.add_face(a, b, c);
  }
  return mesh;
}

Eigen::Vector3d mapPoint(const Eigen::Vector3d& p, const TransformOptions& options) {
  const TriMesh out = transformMesh(pointsMesh({p}), options);
  return toEigen(out.point(TriMesh::VertexHandle(0)));
}

TransformOptions rotation(double x, double y, double z) {
  TransformOptions o;
  o.rotateDegrees = {x, y, z};
  return o;
}

double maxDistance(const TriMesh& a, const TriMesh& b) {
  double d = 0;
  for (auto v : a.vertices())
    d = std::max(d, (a.point(v) - b.point(v)).norm());
  return d;
}

// Faces as vertex triples starting at their smallest index, so windings compare regardless of
// which corner a face starts from.
std::vector<std::array<int, 3>> canonicalFaces(const TriMesh& mesh) {
  auto faces = test::faceIndices(mesh);
  for (auto& f : faces)
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return faces;
}

TEST(Transform, QuarterTurnAboutZMapsXToY) {
  const Eigen::Vector3d q = mapPoint({1, 0, 0}, rotation(0, 0, 90));
  EXPECT_LE((q - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  EXPECT_LE(
      (eulerRotation({0, 0, 90}) * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, 1, 0)).norm(),
      1e-12);
}

TEST(Transform, QuarterTurnsAreExact) {
  const TriMesh bunny = readBunny();
  const TriMesh turned = transformMesh(bunny, rotation(0, 0, -270));
  for (auto v : bunny.vertices()) {
    const auto p = bunny.point(v);
    const auto q = turned.point(v);
    EXPECT_EQ(q[0], -p[1]);
    EXPECT_EQ(q[1], p[0]);
    EXPECT_EQ(q[2], p[2]);
  }
}

TEST(Transform, RotatesAboutXThenYThenZ) {
  // X first takes y to z, then Y takes z to x. The other order would give z.
  EXPECT_LE((mapPoint({0, 1, 0}, rotation(90, 90, 0)) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  // Y first takes x to -z, then Z leaves it; X last would have given y.
  EXPECT_LE((mapPoint({1, 0, 0}, rotation(0, 90, 90)) - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  const Eigen::Matrix3d r = eulerRotation({20, 30, 40});
  EXPECT_LE((r - eulerRotation({0, 0, 40}) * eulerRotation({0, 30, 0}) * eulerRotation({20, 0, 0}))
                .norm(),
            1e-15);
  EXPECT_LE((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
}

TEST(Transform, ScalesThenRotatesThenTranslatesAboutThePivot) {
  TransformOptions o;
  o.translate = {10, 20, 30};
  o.rotateDegrees = {0, 0, 90};
  o.scale = {2, 3, 4};
  o.pivot = {1, 1, 1};
  // p - pivot = (1, 0, 0) -> scaled (2, 0, 0) -> rotated (0, 2, 0) -> + pivot + translate.
  EXPECT_LE((mapPoint({2, 1, 1}, o) - Eigen::Vector3d(11, 23, 31)).norm(), 1e-12);
  // The pivot itself only moves by the translation.
  EXPECT_LE((mapPoint(o.pivot, o) - (o.pivot + o.translate)).norm(), 1e-12);

  const AffineTransform t = affineTransform(o);
  const Eigen::Vector3d p(-0.3, 0.7, 2.5);
  EXPECT_LE((t.linear * p + t.offset -
             (o.translate + o.pivot +
              eulerRotation(o.rotateDegrees) * o.scale.asDiagonal() * (p - o.pivot)))
                .norm(),
            1e-12);
}

TEST(Transform, RotationsAboutOneAxisCompose) {
  const TriMesh bunny = readBunny();
  const TriMesh twice = transformMesh(transformMesh(bunny, rotation(0, 0, 30)), rotation(0, 0, 60));
  const TriMesh once = transformMesh(bunny, rotation(0, 0, 90));
  EXPECT_LE(maxDistance(twice, once), 1e-12 * 16);  // the bunny is about 16 units across
}

TEST(Transform, AppliedTwiceEqualsTheComposedMap) {
  const TriMesh bunny = readBunny();
  TransformOptions a, b;
  a.translate = {0.5, -1, 2};
  a.rotateDegrees = {10, -20, 30};
  a.scale = {1.5, 0.5, -2};
  a.pivot = {1, 2, 3};
  b.translate = {-3, 0.25, 1};
  b.rotateDegrees = {-45, 60, 5};
  b.scale = {-1, 2, 1};
  const TriMesh chained = transformMesh(transformMesh(bunny, a), b);
  const AffineTransform ta = affineTransform(a), tb = affineTransform(b);
  for (auto v : bunny.vertices()) {
    const Eigen::Vector3d expected =
        tb.linear * (ta.linear * toEigen(bunny.point(v)) + ta.offset) + tb.offset;
    EXPECT_LE((toEigen(chained.point(v)) - expected).norm(), 1e-12 * 100);
  }
  // Two mirrors cancel: the winding is back to the original.
  EXPECT_EQ(canonicalFaces(chained), canonicalFaces(bunny));
}

TEST(Transform, InverseStepsRestoreTheMesh) {
  const TriMesh bunny = readBunny();
  TransformOptions forward;
  forward.translate = {3, -2, 7};
  forward.rotateDegrees = {25, -70, 145};
  forward.scale = {2, -0.5, 4};
  forward.pivot = {0.5, 1.5, -1};
  TriMesh mesh = transformMesh(bunny, forward);

  // p = pivot + S^-1 Rx^-1 Ry^-1 Rz^-1 (p' - translate - pivot), one step at a time.
  std::vector<TransformOptions> inverse(6);
  inverse[0].translate = -(forward.translate + forward.pivot);
  inverse[1].rotateDegrees = {0, 0, -forward.rotateDegrees.z()};
  inverse[2].rotateDegrees = {0, -forward.rotateDegrees.y(), 0};
  inverse[3].rotateDegrees = {-forward.rotateDegrees.x(), 0, 0};
  inverse[4].scale = forward.scale.cwiseInverse();
  inverse[5].translate = forward.pivot;
  for (const auto& step : inverse)
    mesh = transformMesh(mesh, step);

  EXPECT_LE(maxDistance(mesh, bunny), 1e-12 * 100);
  EXPECT_EQ(canonicalFaces(mesh), canonicalFaces(bunny));
}

TEST(Transform, RigidMotionKeepsEdgeLengthsAndVolume) {
  const TriMesh bunny = readBunny();
  ASSERT_GT(bunny.n_faces(), 0u);
  TransformOptions o;
  o.rotateDegrees = {17, -33, 71};
  o.translate = {1.5, -2, 0.25};
  o.pivot = {0.3, 0.1, -0.2};
  const TriMesh moved = transformMesh(bunny, o);

  const auto before = test::edgeLengths(bunny);
  const auto after = test::edgeLengths(moved);
  ASSERT_EQ(before.size(), after.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_NEAR(after[i], before[i], 1e-9 * before[i]) << "edge " << i;
  }
  const double volume = test::signedVolume(bunny);
  ASSERT_GT(volume, 0.0);
  EXPECT_NEAR(test::signedVolume(moved), volume, 1e-9 * volume);
  EXPECT_EQ(test::faceIndices(moved), test::faceIndices(bunny));
}

TEST(Transform, VolumeScalesByTheDeterminant) {
  const TriMesh bunny = readBunny();
  const double volume = test::signedVolume(bunny);
  TransformOptions o;
  o.scale = {2, 0.5, 3};
  o.rotateDegrees = {40, 0, -15};
  o.translate = {5, 5, 5};
  EXPECT_NEAR(test::signedVolume(transformMesh(bunny, o)), 3 * volume, 1e-9 * 3 * volume);
}

// Mirroring by any odd number of negative entries keeps the mesh facing outward: the volume
// stays positive, scaled by |det|, and every face normal follows the normal transform L^-T n.
TEST(Transform, MirroringKeepsOutwardOrientation) {
  const TriMesh bunny = readBunny();
  const double volume = test::signedVolume(bunny);
  for (const Eigen::Vector3d& scale :
       {Eigen::Vector3d(-1, 1, 1), Eigen::Vector3d(2, -3, 0.5), Eigen::Vector3d(-1, -1, -2)}) {
    TransformOptions o;
    o.scale = scale;
    o.rotateDegrees = {0, 30, 0};
    const TriMesh mirrored = transformMesh(bunny, o);
    const double det = std::abs(scale.prod());
    EXPECT_NEAR(test::signedVolume(mirrored), det * volume, 1e-9 * det * volume)
        << scale.transpose();

    const Eigen::Matrix3d normalMap = affineTransform(o).linear.inverse().transpose();
    std::size_t flipped = 0;
    for (auto f : bunny.faces()) {
      const Eigen::Vector3d expected = normalMap * toEigen(bunny.calc_face_normal(f));
      if (toEigen(mirrored.calc_face_normal(f)).dot(expected) <= 0) ++flipped;
    }
    EXPECT_EQ(flipped, 0u) << scale.transpose();
    EXPECT_EQ(test::topology(mirrored).boundaryHalfedges, 0u);
  }
}

TEST(Transform, KeepsVertexAndFaceOrder) {
  const TriMesh bunny = readBunny();
  TransformOptions o;
  o.rotateDegrees = {5, 6, 7};
  o.scale = {1, 2, 3};
  const TriMesh out = transformMesh(bunny, o);
  ASSERT_EQ(out.n_vertices(), bunny.n_vertices());
  const AffineTransform t = affineTransform(o);
  for (auto v : bunny.vertices()) {
    EXPECT_EQ(toEigen(out.point(v)), t.linear * toEigen(bunny.point(v)) + t.offset);
  }
  EXPECT_EQ(test::faceIndices(out), test::faceIndices(bunny));
}

TEST(Transform, DefaultsAreTheIdentity) {
  const TriMesh bunny = readBunny();
  EXPECT_TRUE(test::bitIdentical(transformMesh(bunny, {}), bunny));
}

std::string rejectedOption(const TransformOptions& o) {
  try {
    affineTransform(o);
  } catch (const TransformOptionError& e) {
    return e.option();
  }
  return "(accepted)";
}

TEST(Transform, RejectsSingularOrNonFiniteOptions) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  TransformOptions o;
  o.scale = {1, 0, 1};
  EXPECT_EQ(rejectedOption(o), "scale");
  o = {};
  o.scale = {1, 1, nan};
  EXPECT_EQ(rejectedOption(o), "scale");
  o = {};
  o.translate = {inf, 0, 0};
  EXPECT_EQ(rejectedOption(o), "translate");
  o = {};
  o.rotateDegrees = {0, nan, 0};
  EXPECT_EQ(rejectedOption(o), "rotate");
  o = {};
  o.pivot = {0, 0, -inf};
  EXPECT_EQ(rejectedOption(o), "pivot");
  o = {};
  o.scale = {1, 0, 1};
  EXPECT_THROW(transformMesh(pointsMesh({{0, 0, 0}}), o), TransformOptionError);
}

TEST(TransformNode, TransformsAPrimitiveAsTheAlgorithmDoes) {
  Graph graph;
  graph.nodes["source"] = {
      "geobrush.primitive",
      1,
      {{"shape", std::string("rounded_cube")}, {"resolution", std::int64_t{6}}}};
  graph.nodes["move"] = {"geobrush.transform",
                         1,
                         {{"translate", Vec3{1, 2, 3}},
                          {"rotate", Vec3{0, 45, 90}},
                          {"scale", Vec3{-1, 2, 1}},
                          {"pivot", Vec3{0.5, 0, 0}}}};
  graph.connections.push_back({{"source", "mesh"}, {"move", "mesh"}});
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  const auto source = std::dynamic_pointer_cast<const Mesh>(evaluator.output("source", "mesh"));
  const auto moved = std::dynamic_pointer_cast<const Mesh>(evaluator.output("move", "mesh"));
  ASSERT_NE(source, nullptr);
  ASSERT_NE(moved, nullptr);
  TransformOptions o;
  o.translate = {1, 2, 3};
  o.rotateDegrees = {0, 45, 90};
  o.scale = {-1, 2, 1};
  o.pivot = {0.5, 0, 0};
  EXPECT_TRUE(test::bitIdentical(moved->surface, transformMesh(source->surface, o)));
  EXPECT_GT(test::signedVolume(moved->surface), 0.0);
}

TEST(TransformNode, ReportsAZeroScale) {
  Graph graph;
  graph.nodes["source"] = {"geobrush.primitive", 1, {{"resolution", std::int64_t{2}}}};
  graph.nodes["move"] = {"geobrush.transform", 1, {{"scale", Vec3{1, 0, 1}}}};
  graph.connections.push_back({{"source", "mesh"}, {"move", "mesh"}});
  prepareGraph(graph, test::registry());
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(graph);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.error.find("param 'scale'"), std::string::npos) << report.error;
}

using test::DirectContext;

TEST(TransformNode, KeepsVertexColours) {
  const NodeType* type = test::registry().find("geobrush.transform");
  ASSERT_NE(type, nullptr);
  std::vector<Rgb> colours = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  auto input = std::make_shared<const Mesh>(pointsMesh({{0, 0, 0}}), colours);
  DirectContext ctx(*type, {{"mesh", input}}, {{"scale", Vec3{-1, 1, 1}}});
  type->create()->compute(ctx);
  EXPECT_TRUE(ctx.warnings.empty());
  const auto out = std::dynamic_pointer_cast<const Mesh>(ctx.outputs["mesh"]);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->vertexColors, colours);
  EXPECT_EQ(out->surface.point(TriMesh::VertexHandle(1)), TriMesh::Point(-1, 0, 0));
}

}  // namespace
}  // namespace geobrush
