#include "dpm_target.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/derived_store.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/projective_map.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The plane z = 0 over [-half, half]^2 with n x n quads, leaving out the quads whose centre
// `skip` holds.
MeshPtr plane(
    int n, double half,
    const std::function<bool(double, double)>& skip = [](double, double) { return false; }) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.add_vertex({-half + 2 * half * i / n, -half + 2 * half * j / n, 0});
  auto at = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (skip(-half + 2 * half * (i + 0.5) / n, -half + 2 * half * (j + 0.5) / n)) continue;
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

// A flat source map: uv = (x, y) over [-1, 1]^2, R_s = sqrt(2).
std::shared_ptr<Parameterization> flatSource() {
  return test::heightFieldParameterization(12, [](double, double) { return 0.0; });
}

Parameterization asParameterization(ProjectiveStampResult stamp, double scale = 1) {
  Parameterization p;
  p.canvas = std::make_shared<const Canvas>(std::move(stamp.canvas));
  p.uv = std::move(stamp.uv);
  p.normal.assign(p.uv.size(), stamp.origin.normal);
  p.origin = stamp.origin;
  p.scale = scale;
  p.reversedFaces = std::move(stamp.reversedFaces);
  return p;
}

// How many of the points lie outside every uv triangle of the map.
std::size_t outside(const Parameterization& map, const std::vector<Eigen::Vector2d>& points) {
  const DomainLocator locator(map);
  std::size_t count = 0;
  for (const auto& u : points)
    count += !locator.locate(u).inside;
  return count;
}

// Distance from the plane's origin to the triangle of face f projected.
double projectedDistance(const TriMesh& mesh, const Frame& frame, TriMesh::FaceHandle f) {
  std::array<Eigen::Vector3d, 3> t;
  int k = 0;
  for (auto v : mesh.fv_range(f)) {
    const Eigen::Vector2d u = projectOntoPlane(frame, pointOf(mesh, v));
    t[std::size_t(k++)] = {u.x(), u.y(), 0};
  }
  return closestPointOnTriangle(Eigen::Vector3d::Zero(), t[0], t[1], t[2]).norm();
}

std::string rejected(const MeshPtr& mesh, const ProjectiveStampOptions& o,
                     const std::vector<Eigen::Vector2d>& source = flatSource()->uv) {
  try {
    projectiveStamp(StampTarget(mesh), source, o);
  } catch (const ProjectiveStampError& e) {
    return e.option() + ": " + e.what();
  }
  return "(accepted)";
}

TEST(ProjectiveStamp, PlaneMapIsTheRotatedScaledIdentity) {
  const MeshPtr mesh = plane(80, 4);
  const auto source = flatSource();
  for (const auto& [angle, scale] : {std::tuple{0.0, 1.0}, std::tuple{30.0, 0.5},
                                     std::tuple{-135.0, 0.8}, std::tuple{90.0, 1.2}}) {
    SCOPED_TRACE("angle " + std::to_string(angle) + " scale " + std::to_string(scale));
    ProjectiveStampOptions o;
    o.origin = {0.31, -0.22, 0.01};
    o.angleDegrees = angle;
    o.scale = scale;
    const ProjectiveStampResult stamp = projectiveStamp(StampTarget(mesh), source->uv, o);
    const Eigen::Vector3d origin(0.31, -0.22, 0);
    EXPECT_LE((stamp.canvas.originPoint - origin).norm(), 1e-12);
    EXPECT_EQ(stamp.origin.normal, Eigen::Vector3d::UnitZ());
    const double a = angle * std::numbers::pi / 180;
    ASSERT_EQ(stamp.uv.size(), stamp.canvas.surface.n_vertices());
    for (auto v : stamp.canvas.surface.vertices()) {
      const Eigen::Vector3d d = pointOf(stamp.canvas.surface, v) - origin;
      const Eigen::Vector2d expected = Eigen::Vector2d(std::cos(a) * d.x() + std::sin(a) * d.y(),
                                                       -std::sin(a) * d.x() + std::cos(a) * d.y()) /
                                       scale;
      ASSERT_LE((stamp.uv[std::size_t(v.idx())] - expected).norm(), 1e-12) << v.idx();
    }
    EXPECT_EQ(meshStats(stamp.canvas.surface).boundaryLoops, 1u);
    EXPECT_EQ(std::count(stamp.reversedFaces.begin(), stamp.reversedFaces.end(), 1), 0);
    EXPECT_DOUBLE_EQ(stamp.radius, 1.25 * std::sqrt(2.0));

    // The canvas is exactly the faces whose projection meets the disc of the source plus margin.
    std::vector<char> inCanvas(mesh->surface.n_faces(), 0);
    for (int f : stamp.canvas.sourceFace)
      inCanvas[std::size_t(f)] = 1;
    for (auto f : mesh->surface.faces()) {
      const double distance = projectedDistance(mesh->surface, stamp.origin, f);
      EXPECT_EQ(bool(inCanvas[std::size_t(f.idx())]), distance <= scale * stamp.radius)
          << f.idx() << " at " << distance;
    }
    // So its uv image holds the source map and the margin.
    std::vector<Eigen::Vector2d> widened;
    for (const auto& u : source->uv)
      widened.push_back(u * (1.25 * (1 - 1e-9)));
    EXPECT_EQ(outside(asParameterization(stamp), widened), 0u);
  }
}

TEST(ProjectiveStamp, RefusesADiscHoldingAHoleUnlessItKeepsHoles) {
  // A hole of two by two quads near the origin.
  const MeshPtr mesh =
      plane(40, 4, [](double x, double y) { return std::abs(x - 0.6) < 0.2 && std::abs(y) < 0.2; });
  ProjectiveStampOptions o;
  o.origin = {0, 0, 0};
  EXPECT_TRUE(test::contains(rejected(mesh, o), "mesh: the stamp's disc holds a hole"));
  o.keepHoles = true;
  const ProjectiveStampResult stamp = projectiveStamp(StampTarget(mesh), flatSource()->uv, o);
  EXPECT_EQ(meshStats(stamp.canvas.surface).boundaryLoops, 2u);
  // The boundary is the outer loop.
  for (int v : stamp.canvas.boundary)
    EXPECT_GT(stamp.uv[std::size_t(v)].norm(), 1.25 * std::sqrt(2.0));
}

TEST(ProjectiveStamp, RefusesBadInput) {
  const MeshPtr mesh = plane(20, 4);
  ProjectiveStampOptions o;
  o.origin = {0, 0, 1};  // 1 from the plane, its diagonal about 11.3
  EXPECT_TRUE(test::contains(rejected(mesh, o), "origin: "));
  o = {};
  o.origin = {3.5, 0, 0};  // the disc runs off the plane's edge
  EXPECT_TRUE(test::contains(rejected(mesh, o), "scale: the stamp runs off"));
  o = {};
  o.scale = 0;
  EXPECT_TRUE(test::contains(rejected(mesh, o), "scale: "));
  o = {};
  o.margin = -1;
  EXPECT_TRUE(test::contains(rejected(mesh, o), "margin: "));
  o = {};
  o.view = {0, std::nan(""), 0};
  EXPECT_TRUE(test::contains(rejected(mesh, o), "view: "));
  o = {};
  EXPECT_TRUE(test::contains(rejected(mesh, o, {}), "source: "));
  EXPECT_TRUE(test::contains(rejected(mesh, o, {Eigen::Vector2d::Zero()}), "source: "));
  EXPECT_THROW(StampTarget(std::make_shared<const Mesh>()), ProjectiveStampError);
  // A whole closed surface under the disc.
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  o = {};
  o.origin = pointOf(sphere->surface, 0);
  o.scale = 5;
  EXPECT_TRUE(test::contains(rejected(sphere, o), "scale: "));
}

// On the shared unit sphere, seen from the stamp's normal: one loop, no fold, the source covered.
TEST(ProjectiveStamp, StampsTheSharedSphere) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const auto source = flatSource();
  ProjectiveStampOptions o;
  o.origin = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  o.scale = 0.3;
  o.angleDegrees = 20;
  const ProjectiveStampResult stamp = projectiveStamp(StampTarget(sphere), source->uv, o);
  EXPECT_EQ(meshStats(stamp.canvas.surface).boundaryLoops, 1u);
  EXPECT_EQ(std::count(stamp.reversedFaces.begin(), stamp.reversedFaces.end(), 1), 0);
  EXPECT_LT(stamp.canvas.surface.n_faces(), sphere->surface.n_faces() / 2);
  EXPECT_GT(stamp.origin.normal.dot(o.origin), 0.99);
  for (const auto& u : stamp.uv)
    ASSERT_TRUE(u.allFinite());
  EXPECT_EQ(outside(asParameterization(stamp, o.scale), source->uv), 0u);
}

using test::DirectContext;

const NodeType& stampType() {
  const NodeType* type = test::registry().find("geobrush.dpm_target");
  EXPECT_NE(type, nullptr) << (test::registryLoadErrors().empty() ? ""
                                                                  : test::registryLoadErrors()[0]);
  return *type;
}

TEST(DpmTargetNode, OutputsTheStampWithRotationAndScale) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const auto source = flatSource();
  const ParamMap params{{"origin", Vec3{0.0, 0.0, 1.0}}, {"angle", 40.0}, {"scale", 0.3}};
  auto run = [&] {
    DirectContext ctx(stampType(), {{"mesh", sphere}, {"source", source}}, params);
    stampType().create()->compute(ctx);
    return std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["parameterization"]);
  };
  const auto out = run();
  ASSERT_NE(out, nullptr);
  ProjectiveStampOptions o;
  o.origin = {0, 0, 1};
  o.angleDegrees = 40;
  o.scale = 0.3;
  const ProjectiveStampResult stamp = projectiveStamp(StampTarget(sphere), source->uv, o);
  EXPECT_EQ(out->canvas->source, sphere);
  EXPECT_EQ(out->canvas->sourceFace, stamp.canvas.sourceFace);
  EXPECT_EQ(out->uv, stamp.uv);
  EXPECT_EQ(out->reversedFaces, stamp.reversedFaces);
  EXPECT_EQ(out->normal, std::vector<Eigen::Vector3d>(out->uv.size(), stamp.origin.normal));
  EXPECT_DOUBLE_EQ(out->rotation, 40 * std::numbers::pi / 180);
  EXPECT_EQ(out->scale, 0.3);
  EXPECT_EQ(run()->contentHash(), out->contentHash());
}

// Dragging the stamp over one target builds its nearest-point search once, and each position
// gives what a fresh node gives.
TEST(DpmTargetNode, ADragSharesTheTargetsSearch) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const auto source = flatSource();
  const auto derived = std::make_shared<DerivedStore>();
  const auto node = stampType().create();
  for (double x : {0.0, 0.1, 0.2}) {
    const ParamMap params{{"origin", Vec3{x, 0.0, 1.0}}, {"scale", 0.3}};
    DirectContext ctx(stampType(), {{"mesh", sphere}, {"source", source}}, params, derived);
    node->compute(ctx);
    DirectContext fresh(stampType(), {{"mesh", sphere}, {"source", source}}, params);
    stampType().create()->compute(fresh);
    EXPECT_EQ(ctx.outputs["parameterization"]->contentHash(),
              fresh.outputs["parameterization"]->contentHash());
  }
  EXPECT_EQ(derived->builds(), 1u);
}

TEST(DpmTargetNode, NamesThePortOrParamOfABadInput) {
  auto where = [](const MeshPtr& mesh, const ParameterizationPtr& source,
                  const ParamMap& params) -> std::string {
    DirectContext ctx(stampType(), {{"mesh", mesh}, {"source", source}}, params);
    try {
      stampType().create()->compute(ctx);
    } catch (const NodeError& e) {
      return e.where();
    }
    return "(accepted)";
  };
  const MeshPtr holed =
      plane(40, 4, [](double x, double y) { return std::abs(x - 0.6) < 0.2 && std::abs(y) < 0.2; });
  const auto source = flatSource();
  EXPECT_EQ(where(holed, source, {}), "input 'mesh'");
  EXPECT_EQ(where(holed, source, {{"keep_holes", true}}), "(accepted)");
  EXPECT_EQ(where(std::make_shared<const Mesh>(), source, {}), "input 'mesh'");
  EXPECT_EQ(where(plane(20, 4), std::make_shared<const Parameterization>(), {}), "input 'source'");
  EXPECT_EQ(where(plane(20, 4), source, {{"origin", Vec3{0.0, 0.0, 2.0}}}), "param 'origin'");
  EXPECT_EQ(where(plane(20, 4), source, {{"scale", -1.0}}), "param 'scale'");
}

}  // namespace
}  // namespace geobrush
