#include "emd_signal.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/vertex_fields.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

TriMesh sphereOfRadius(double radius) {
  TriMesh sphere = test::icosphere(4);
  for (auto v : sphere.vertices())
    sphere.set_point(v, sphere.point(v) * radius);
  return sphere;
}

TriMesh moved(TriMesh mesh, const Eigen::Isometry3d& rigid) {
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const Eigen::Vector3d q = rigid * Eigen::Vector3d(p[0], p[1], p[2]);
    mesh.set_point(v, toPoint(q));
  }
  return mesh;
}

// T1: cotangent weights reproduce linear functions, so a plane has no detail, border included
// (there Delta lies in the plane), wherever the plane lies.
TEST(EmdSignal, IsZeroOnAPlane) {
  const Eigen::Isometry3d rigid = Eigen::Translation3d(-3, 1, 2) *
                                  Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 1, 1).normalized());
  const MeshPtr plane = test::heightGrid(
      16, [](double, double) { return 0.0; }, rigid);
  const EmdSignal signal = emdSignal(plane->surface, {});
  ASSERT_EQ(signal.g.size(), plane->surface.n_vertices());
  for (double g : signal.g)
    EXPECT_LT(std::abs(g), 1e-12);
}

// T1: on a sphere of radius R, g_i = -4 A_i / R (Delta x = -2 H n, H = 1 / R, times 2 A_i); with
// area_normalize, -4 / R whatever the resolution.
TEST(EmdSignal, IsFourAreasOverTheRadiusInwardOnASphere) {
  const double radius = 3.0;
  const TriMesh sphere = sphereOfRadius(radius);
  const EmdSignal raw = emdSignal(sphere, {});
  const EmdSignal density = emdSignal(sphere, {.areaNormalize = true});
  for (std::size_t i = 0; i < raw.g.size(); ++i) {
    const double expected = -4 * raw.area[i] / radius;
    EXPECT_NEAR(raw.g[i], expected, 0.05 * std::abs(expected)) << i;
    EXPECT_NEAR(density.g[i], -4 / radius, 0.05 * 4 / radius) << i;
  }
}

// T1: g is intrinsic to the shape: a rigid motion changes it by rounding only.
TEST(EmdSignal, IsUnchangedByRigidMotionsOfARealMesh) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const Eigen::Isometry3d rigid = Eigen::Translation3d(0.5, -2, 1) *
                                  Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 3).normalized());
  const EmdSignal before = emdSignal(bunny->surface, {});
  const EmdSignal after = emdSignal(moved(bunny->surface, rigid), {});
  const double size = boundingDiagonal(bunny->surface);
  double largest = 0;
  for (std::size_t i = 0; i < before.g.size(); ++i) {
    EXPECT_NEAR(after.g[i], before.g[i], 1e-12 * size) << i;
    largest = std::max(largest, std::abs(before.g[i]));
  }
  EXPECT_GT(largest, 1e-6 * size);  // the bunny has detail to keep
}

const NodeType& signalNode() {
  const NodeType* type = test::registry().find("geobrush.emd_signal");
  EXPECT_NE(type, nullptr);
  return *type;
}

TEST(EmdSignalNode, WritesGAndAreaOnTheMeshItRead) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  test::DirectContext ctx(signalNode(), {{"mesh", bunny}});
  signalNode().create()->compute(ctx);
  const auto fields = std::dynamic_pointer_cast<const VertexFields>(ctx.outputs["signal"]);
  ASSERT_TRUE(fields);
  EXPECT_EQ(fields->names(), (std::vector<std::string>{"g", "area"}));
  EXPECT_EQ(fields->mismatch(bunny->surface), "");
  EXPECT_EQ(fields->column("g"), emdSignal(bunny->surface, {}).g);
}

TEST(EmdSignalNode, RefusesToNormalizeByTheAreaOfALooseVertex) {
  TriMesh mesh = test::heightGrid(2, [](double, double) { return 0.0; })->surface;
  mesh.add_vertex({5, 5, 5});
  const auto input = std::make_shared<const Mesh>(mesh);
  test::DirectContext ctx(signalNode(), {{"mesh", input}}, {{"area_normalize", true}});
  try {
    signalNode().create()->compute(ctx);
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "input 'mesh'");
    EXPECT_TRUE(test::contains(e.what(), "vertex 9 has no area"));
  }
}

}  // namespace
}  // namespace geobrush
