#include "dem.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

// The plane z = 0 over [-half, half]^2 with n x n quads.
MeshPtr plane(int n, double half) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.add_vertex({-half + 2 * half * i / n, -half + 2 * half * j / n, 0});
  auto at = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return std::make_shared<const Mesh>(std::move(mesh));
}

// E_s of a flat source canvas: uv = (x, y) over [-1, 1]^2, |uv| up to sqrt(2).
const std::vector<Eigen::Vector2d>& sourceUv() {
  static const auto source =
      test::heightFieldParameterization(12, [](double, double) { return 0.0; });
  return source->uv;
}

Parameterization asParameterization(TargetDemResult dem) {
  Parameterization p;
  p.canvas = std::make_shared<const Canvas>(std::move(dem.canvas));
  p.uv = std::move(dem.uv);
  p.normal = std::move(dem.normal);
  p.origin = dem.origin;
  return p;
}

// Every source uv lies in some uv triangle of the target canvas.
void expectCovers(const Parameterization& target, const std::vector<Eigen::Vector2d>& source,
                  double factor = 1) {
  const DomainLocator locator(target);
  std::size_t outside = 0;
  for (const auto& u : source)
    outside += !locator.locate(factor * u).inside;
  EXPECT_EQ(outside, 0u);
}

// The rule of targetExponentialMap: boundary vertices lie at least R from the domain origin.
void expectBoundaryBeyondRequired(const TargetDemResult& dem) {
  for (int b : dem.canvas.boundary)
    EXPECT_GE(dem.uv[b].norm(), dem.requiredRadius) << "boundary vertex " << b;
}

std::string rejected(const MeshPtr& mesh, const TargetDemOptions& o,
                     const std::vector<Eigen::Vector2d>& source = sourceUv()) {
  try {
    targetExponentialMap(mesh, source, o);
  } catch (const TargetDemError& e) {
    return e.option() + ": " + e.what();
  }
  return "(accepted)";
}

TEST(Dem, PlaneMapIsTheRotatedScaledIdentity) {
  const MeshPtr mesh = plane(80, 4);
  for (const auto& [angle, scale] : {std::tuple{0.0, 1.0}, std::tuple{30.0, 0.5},
                                     std::tuple{-135.0, 0.8}, std::tuple{90.0, 1.2}}) {
    SCOPED_TRACE("angle " + std::to_string(angle) + " scale " + std::to_string(scale));
    TargetDemOptions o;
    o.origin = {0.31, -0.22, 0.01};
    o.angleDegrees = angle;
    o.scale = scale;
    const TargetDemResult dem = targetExponentialMap(mesh, sourceUv(), o);
    const Eigen::Vector3d origin(0.31, -0.22, 0);
    EXPECT_LE((dem.canvas.originPoint - origin).norm(), 1e-12);
    const double a = angle * std::numbers::pi / 180;
    ASSERT_EQ(dem.uv.size(), dem.canvas.surface.n_vertices());
    for (auto v : dem.canvas.surface.vertices()) {
      const Eigen::Vector3d d = toEigen(dem.canvas.surface.point(v)) - origin;
      const Eigen::Vector2d expected = Eigen::Vector2d(std::cos(a) * d.x() + std::sin(a) * d.y(),
                                                       -std::sin(a) * d.x() + std::cos(a) * d.y()) /
                                       scale;
      ASSERT_LE((dem.uv[v.idx()] - expected).norm(), 1e-9) << "vertex " << v.idx();
      EXPECT_LE((dem.normal[v.idx()] - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    }
    EXPECT_EQ(test::topology(dem.canvas.surface).boundaryLoops, 1u);
    EXPECT_DOUBLE_EQ(dem.requiredRadius, 1.25 * std::sqrt(2.0));
    expectBoundaryBeyondRequired(dem);
    // Grown only as far as needed: the growth follows Dijkstra distances, which on this grid
    // (diagonals one way only) overestimate Euclidean ones by up to sqrt(2), so the last
    // vertices fixed lie up to that factor beyond the required radius plus two edges.
    double largest = 0;
    for (const auto& u : dem.uv)
      largest = std::max(largest, u.norm());
    EXPECT_LE(largest, std::sqrt(2.0) * (dem.requiredRadius + 0.3 / scale));
    const Parameterization p = asParameterization(dem);
    expectCovers(p, sourceUv(), 1.25);
  }
}

// A preferred disk (the source cage's) is covered where the target allows it; where covering it
// would wrap the canvas around the target, the canvas covers the required disk alone.
TEST(Dem, CoversThePreferredDiskWhereTheTargetAllows) {
  TargetDemOptions o;
  o.origin = {0.1, 0.2, 0};
  o.preferredRadius = 2.5;  // beyond 1.25 sqrt(2), the required radius of sourceUv()
  const TargetDemResult wide = targetExponentialMap(plane(96, 6), sourceUv(), o);
  EXPECT_DOUBLE_EQ(wide.requiredRadius, 2.5);
  expectBoundaryBeyondRequired(wide);
  expectCovers(asParameterization(wide), sourceUv(), 2.5 / std::sqrt(2.0));

  // On the unit sphere at scale 0.35, a disk of radius 6 would be 2.1 geodesic radii: more than
  // half of the sphere.
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  o.origin = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  o.scale = 0.35;
  o.preferredRadius = 6;
  const TargetDemResult fallback = targetExponentialMap(sphere, sourceUv(), o);
  EXPECT_DOUBLE_EQ(fallback.requiredRadius, 1.25 * std::sqrt(2.0));
  o.preferredRadius = 0;
  const TargetDemResult required = targetExponentialMap(sphere, sourceUv(), o);
  EXPECT_EQ(fallback.canvas.sourceVertex, required.canvas.sourceVertex);
  EXPECT_EQ(fallback.uv, required.uv);
}

TEST(Dem, CanvasIsAFullCanvasOfTheTarget) {
  const MeshPtr mesh = plane(40, 3);
  TargetDemOptions o;
  o.origin = {0.5, 0.4, 0};
  o.scale = 0.7;
  const TargetDemResult dem = targetExponentialMap(mesh, sourceUv(), o);
  const Canvas& c = dem.canvas;
  EXPECT_EQ(c.source, mesh);
  ASSERT_EQ(c.sourceVertex.size(), c.surface.n_vertices());
  ASSERT_EQ(c.sourceFace.size(), c.surface.n_faces());
  EXPECT_TRUE(std::is_sorted(c.sourceFace.begin(), c.sourceFace.end()));
  for (auto v : c.surface.vertices())
    EXPECT_EQ(c.surface.point(v),
              mesh->surface.point(TriMesh::VertexHandle(c.sourceVertex[v.idx()])));
  ASSERT_GE(c.originFace, 0);
  EXPECT_LE((c.originPoint - Eigen::Vector3d(0.5, 0.4, 0)).norm(), 1e-12);
  EXPECT_EQ(c.boundary.size(), test::topology(c.surface).boundaryHalfedges);
  for (std::size_t i = 0; i < c.boundary.size(); ++i) {
    const auto h =
        c.surface.find_halfedge(TriMesh::VertexHandle(c.boundary[i]),
                                TriMesh::VertexHandle(c.boundary[(i + 1) % c.boundary.size()]));
    ASSERT_TRUE(h.is_valid());
    EXPECT_TRUE(c.surface.is_boundary(h));
  }
  EXPECT_LE(dem.uv[c.originVertex].norm(), 0.1 / 0.7);
}

TEST(Dem, SphereRadiusFollowsGeodesicDistance) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  TargetDemOptions o;
  o.origin = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  o.scale = 0.35;
  const TargetDemResult dem = targetExponentialMap(sphere, sourceUv(), o);
  const Eigen::Vector3d n = dem.canvas.originPoint.normalized();
  double worst = 0;
  for (auto v : dem.canvas.surface.vertices()) {
    const Eigen::Vector3d p = toEigen(dem.canvas.surface.point(v)).normalized();
    const double geodesic = std::acos(std::clamp(p.dot(n), -1.0, 1.0));
    worst = std::max(worst, std::abs(dem.uv[v.idx()].norm() * o.scale - geodesic));
  }
  // The icosphere's edges are about 0.15 long; the DEM's error stays within a third of that.
  EXPECT_LE(worst, 0.05);
  EXPECT_EQ(test::topology(dem.canvas.surface).boundaryLoops, 1u);
  expectBoundaryBeyondRequired(dem);
  expectCovers(asParameterization(dem), sourceUv(), 1.25);
}

TEST(Dem, RealTargetsGiveFiniteCoveringCanvases) {
  for (const auto& [name, vertex] :
       {std::tuple{"bunny_small.obj", 1000}, std::tuple{"nefertiti.obj", 20000}}) {
    SCOPED_TRACE(name);
    const MeshPtr mesh = readMesh(test::meshPath(name)).mesh;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (auto v : mesh->surface.vertices()) {
      lo = lo.cwiseMin(toEigen(mesh->surface.point(v)));
      hi = hi.cwiseMax(toEigen(mesh->surface.point(v)));
    }
    TargetDemOptions o;
    o.origin = toEigen(mesh->surface.point(TriMesh::VertexHandle(vertex)));
    // The required disk's radius is 6% of the bounding-box diagonal.
    o.scale = 0.06 * (hi - lo).norm() / (1.25 * std::sqrt(2.0));
    o.angleDegrees = 25;
    const TargetDemResult dem = targetExponentialMap(mesh, sourceUv(), o);
    for (const auto& u : dem.uv)
      ASSERT_TRUE(u.allFinite());
    for (const auto& n : dem.normal)
      EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_EQ(test::topology(dem.canvas.surface).boundaryLoops, 1u);
    EXPECT_EQ(test::topology(dem.canvas.surface).nonManifoldVertices, 0u);
    expectBoundaryBeyondRequired(dem);
    expectCovers(asParameterization(dem), sourceUv());
    const TargetDemResult again = targetExponentialMap(mesh, sourceUv(), o);
    EXPECT_EQ(dem.uv, again.uv);
    EXPECT_EQ(dem.canvas.sourceFace, again.canvas.sourceFace);
    EXPECT_EQ(dem.canvas.boundary, again.canvas.boundary);
  }
}

TEST(Dem, RejectsBadInput) {
  const MeshPtr mesh = plane(20, 3);
  TargetDemOptions o;
  for (double scale : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                       std::numeric_limits<double>::infinity()}) {
    o.scale = scale;
    EXPECT_TRUE(test::contains(rejected(mesh, o), "scale: must be a finite number > 0"));
  }
  o = {};
  o.margin = -0.1;
  EXPECT_TRUE(test::contains(rejected(mesh, o), "margin:"));
  o = {};
  o.origin = {0, 0, 1};
  EXPECT_TRUE(test::contains(rejected(mesh, o), "away from the target surface"));
  o.origin = {3, 0.1, 0};
  EXPECT_TRUE(test::contains(rejected(mesh, o), "origin: the origin lies on a boundary"));
  // Near the boundary the required disk runs off the target.
  o.origin = {2.5, 0, 0};
  EXPECT_TRUE(test::contains(rejected(mesh, o), "scale: the required domain runs off"));
  o = {};
  EXPECT_TRUE(test::contains(rejected(mesh, o, {}), "source:"));

  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  o = {};
  o.origin = {0, 1, 0};
  o.scale = 2;  // the disk's radius, 3.5, is more than half the way around the unit sphere
  const std::string message = rejected(sphere, o);
  EXPECT_TRUE(test::contains(message, "scale:"));
  EXPECT_TRUE(test::contains(message, "would wrap around it: use a smaller scale"));
}

// A plane with a square hole near the origin: refused as it is, kept inside the canvas (one more
// boundary loop, every source uv still covered around it) when keepHoles asks for it.
TEST(Dem, KeepsTheMeshHolesItIsAskedTo) {
  TriMesh holed = plane(40, 4)->surface;
  holed.request_face_status();
  holed.request_edge_status();
  holed.request_vertex_status();
  for (auto f : holed.faces()) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (auto v : holed.fv_range(f))
      centre += toEigen(holed.point(v)) / 3;
    if ((centre - Eigen::Vector3d(0.9, 0.4, 0)).cwiseAbs().maxCoeff() < 0.5)
      holed.delete_face(f, true);
  }
  holed.garbage_collection();
  const MeshPtr mesh = std::make_shared<const Mesh>(std::move(holed));
  TargetDemOptions o;
  EXPECT_TRUE(test::contains(rejected(mesh, o), "boundary"));
  o.keepHoles = true;
  const TargetDemResult dem = targetExponentialMap(mesh, sourceUv(), o);
  EXPECT_EQ(meshStats(dem.canvas.surface).boundaryLoops, 2u);
  // The outer loop lies beyond the required disk.
  for (int v : dem.canvas.boundary)
    EXPECT_GT(dem.uv[std::size_t(v)].norm(), dem.requiredRadius * 0.99);
}

using test::DirectContext;

TEST(DemNode, OutputsTheTargetParameterization) {
  const NodeType* type = test::registry().find("geobrush.dem");
  ASSERT_NE(type, nullptr);
  const MeshPtr mesh = plane(40, 3);
  const auto source = test::heightFieldParameterization(12, [](double, double) { return 0.0; });
  DirectContext ctx(*type, {{"mesh", mesh}, {"source", source}},
                    {{"origin", Vec3{0.2, 0.1, 0}}, {"angle", 40.0}, {"scale", 0.6}});
  type->create()->compute(ctx);
  const auto out =
      std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["parameterization"]);
  ASSERT_NE(out, nullptr);
  TargetDemOptions o;
  o.origin = {0.2, 0.1, 0};
  o.angleDegrees = 40;
  o.scale = 0.6;
  const TargetDemResult dem = targetExponentialMap(mesh, source->uv, o);
  EXPECT_EQ(out->canvas->source, mesh);
  EXPECT_EQ(out->canvas->sourceFace, dem.canvas.sourceFace);
  EXPECT_EQ(out->uv, dem.uv);
  EXPECT_EQ(out->normal, dem.normal);
  EXPECT_EQ(out->origin.uAxis, dem.origin.uAxis);
  EXPECT_DOUBLE_EQ(out->rotation, 40 * std::numbers::pi / 180);
  EXPECT_EQ(out->scale, 0.6);
  EXPECT_TRUE(out->reversedFaces.empty());
  expectCovers(*out, source->uv);

  for (double scale : {0.0, -2.0}) {
    DirectContext bad(*type, {{"mesh", mesh}, {"source", source}}, {{"scale", scale}});
    try {
      type->create()->compute(bad);
      ADD_FAILURE() << "accepted scale " << scale;
    } catch (const NodeError& e) {
      EXPECT_EQ(e.where(), "param 'scale'");
    }
  }
}

}  // namespace
}  // namespace geobrush
