#include "dpm_lift.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/projective_map.hpp"
#include "geobrush/region.hpp"
#include "geobrush/surface_point.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

double bump(double x, double y) {
  const double s = 1 - (x * x + y * y) / (0.6 * 0.6);
  return s > 0 ? 0.8 * s * s * s : 0.0;
}

// The height field z(x, y) over [-half, half]^2 with n x n quads.
MeshPtr grid(int n, double half, const std::function<double(double, double)>& z) {
  TriMesh mesh =
      test::heightGrid(n, [&](double x, double y) { return z(half * x, half * y); })->surface;
  for (auto v : mesh.vertices()) {
    auto p = mesh.point(v);
    mesh.set_point(v, {half * p[0], half * p[1], p[2]});
  }
  return std::make_shared<const Mesh>(std::move(mesh));
}

// The plane z = 0 over [-half, half]^2 with n x n quads.
MeshPtr plane(int n, double half) {
  return grid(n, half, [](double, double) { return 0.0; });
}

// The target stamp geobrush.dpm_target makes.
ParameterizationPtr stamp(const MeshPtr& mesh, const ParameterizationPtr& source,
                          const ParamMap& params) {
  const test::NodeRun run =
      test::runNode("geobrush.dpm_target", {{"mesh", mesh}, {"source", source}}, params);
  const auto map = run.get<Parameterization>("parameterization");
  EXPECT_NE(map, nullptr);
  return map;
}

struct Lifted {
  MeshPtr draft;
  std::vector<std::string> warnings;
};

Lifted lift(const ParameterizationPtr& source, const ParameterizationPtr& target,
            const ParamMap& params = {}, const Region2DPtr& region = nullptr) {
  std::map<std::string, ValuePtr, std::less<>> inputs{{"source", source}, {"target", target}};
  if (region) inputs["region"] = region;
  const test::NodeRun run = test::runNode("geobrush.dpm_lift", std::move(inputs), params);
  return {run.get<Mesh>("draft"), run.warnings};
}

// The bump's map: uv = (x, y), h = z (the frame at the origin, normal +z).
ParameterizationPtr bumpSource() {
  return test::heightFieldParameterization(24, bump);
}

// A bump pasted onto a plane lands at the rotated, scaled positions with heights lambda h; at
// angle 0 and scale 1 on the plane through its own origin it is reproduced.
TEST(DpmLift, BumpOntoAPlaneLandsRotatedAndScaled) {
  const auto source = bumpSource();
  const MeshPtr target = plane(80, 4);
  for (const auto& [angle, scale] : {std::tuple{0.0, 1.0}, std::tuple{30.0, 0.5},
                                     std::tuple{-135.0, 0.8}, std::tuple{90.0, 1.7}}) {
    SCOPED_TRACE("angle " + std::to_string(angle) + " scale " + std::to_string(scale));
    const bool identity = angle == 0 && scale == 1;
    const Eigen::Vector3d origin =
        identity ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.3, -0.2, 0);
    const auto map =
        stamp(target, source,
              {{"origin", Vec3{origin.x(), origin.y(), 0.0}}, {"angle", angle}, {"scale", scale}});
    ASSERT_NE(map, nullptr);
    const Lifted lifted = lift(source, map);
    ASSERT_NE(lifted.draft, nullptr);
    EXPECT_TRUE(lifted.warnings.empty());
    const TriMesh& canvas = source->canvas->surface;
    ASSERT_EQ(lifted.draft->surface.n_vertices(), canvas.n_vertices());
    EXPECT_EQ(test::faceIndices(lifted.draft->surface), test::faceIndices(canvas));
    const double a = angle * std::numbers::pi / 180;
    const Eigen::Vector3d eu(std::cos(a), std::sin(a), 0), ev(-std::sin(a), std::cos(a), 0);
    for (auto v : canvas.vertices()) {
      const Eigen::Vector3d p = pointOf(canvas, v);
      const Eigen::Vector3d expected =
          origin + scale * (p.x() * eu + p.y() * ev + p.z() * Eigen::Vector3d::UnitZ());
      ASSERT_LE((pointOf(lifted.draft->surface, v) - expected).norm(), 1e-12) << v.idx();
      if (identity) {
        EXPECT_LE((pointOf(lifted.draft->surface, v) - p).norm(), 1e-15);
      }
    }
  }
}

// The same map as source and target: a flat canvas is put back where it is (X_T inverts E1).
TEST(DpmLift, IdenticalFlatSourceAndTargetReproduceTheCanvas) {
  const MeshPtr mesh = test::heightGrid(30, [](double x, double y) { return 0.3 * x - 0.2 * y; });
  const int face = nearestSurfacePoint(mesh->surface, {0.05, 0.1, 0.3 * 0.05 - 0.2 * 0.1}).face;
  const auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(mesh, face, 0.8));
  ProjectiveMapOptions o;
  o.angleDegrees = 17;
  ProjectiveMapResult map = projectiveMap(canvas, o);
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  param->uv = map.uv;
  param->normal.assign(map.uv.size(), map.origin.normal);
  param->origin = map.origin;
  const Lifted lifted = lift(param, param);
  ASSERT_NE(lifted.draft, nullptr);
  EXPECT_TRUE(lifted.warnings.empty());
  for (auto v : canvas->surface.vertices())
    EXPECT_LE((pointOf(lifted.draft->surface, v) - pointOf(canvas->surface, v)).norm(), 1e-13);
}

// Where u leaves the target canvas the plane is extrapolated, exactly on a flat target, and
// counted in a warning.
TEST(DpmLift, ExtrapolatesBeyondTheTargetCanvasAndSaysSo) {
  const auto source = bumpSource();
  // A target canvas over [-0.5, 0.5]^2 only: uv = (x, y).
  auto small = std::make_shared<Parameterization>(
      *test::heightFieldParameterization(6, [](double, double) { return 0.0; }));
  auto canvas = std::make_shared<Canvas>(*small->canvas);
  for (auto v : canvas->surface.vertices())
    canvas->surface.set_point(v, canvas->surface.point(v) * 0.5);
  small->canvas = canvas;
  for (auto& u : small->uv)
    u *= 0.5;
  const Lifted lifted = lift(source, small);
  ASSERT_NE(lifted.draft, nullptr);
  ASSERT_EQ(lifted.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(lifted.warnings[0], "map outside the target canvas"));
  for (auto v : source->canvas->surface.vertices())
    EXPECT_LE((pointOf(lifted.draft->surface, v) - pointOf(source->canvas->surface, v)).norm(),
              1e-12);
}

// offset_direction = surface follows the target's normals: on a cylinder the bump stands out
// radially.
TEST(DpmLift, SurfaceDirectionFollowsTheTargetNormals) {
  const double rho = 3;
  const MeshPtr cylinder =
      grid(60, 2, [rho](double x, double) { return std::sqrt(rho * rho - x * x) - rho; });
  const auto source = bumpSource();
  const auto map = stamp(cylinder, source, {{"origin", Vec3{0.0, 0.0, 0.0}}, {"scale", 0.5}});
  ASSERT_NE(map, nullptr);
  const Lifted plane = lift(source, map);
  const Lifted surface = lift(source, map, {{"offset_direction", std::string("surface")}});
  ASSERT_NE(surface.draft, nullptr);
  const Eigen::Vector3d axis(0, 0, -rho);  // the cylinder's axis runs along y through here
  for (auto v : source->canvas->surface.vertices()) {
    const double h = pointOf(source->canvas->surface, v).z();
    const Eigen::Vector3d p = pointOf(surface.draft->surface, v);
    // With the view's direction the bump stands along +z instead: off the middle, not radially.
    const Eigen::Vector3d q = pointOf(plane.draft->surface, v);
    if (std::abs(q.x()) > 0.2 && h > 0.1) {
      EXPECT_GT((p - q).norm(), 1e-3) << v.idx();
    }
    Eigen::Vector3d radial = p - axis;
    radial.y() = 0;
    // Faceted normals: within a thousandth of the radius.
    EXPECT_NEAR(radial.norm(), rho + 0.5 * h, 2e-3) << v.idx();
  }
}

// Only the draft support is lifted where a region is connected; the rest keeps its place.
TEST(DpmLift, ARegionLiftsItsDraftSupportOnly) {
  const auto source = bumpSource();
  const auto map = stamp(plane(40, 4), source,
                         {{"origin", Vec3{0.5, 0.1, 0.0}}, {"angle", 60.0}, {"scale", 0.7}});
  ASSERT_NE(map, nullptr);
  const Lifted whole = lift(source, map);
  auto region = std::make_shared<Region2D>();
  const TriMesh& canvas = source->canvas->surface;
  for (auto v : canvas.vertices())
    if (source->uv[std::size_t(v.idx())].norm() < 0.5) region->draftSupport.push_back(v.idx());
  ASSERT_GT(region->draftSupport.size(), 10u);
  const Lifted part = lift(source, map, {}, region);
  ASSERT_NE(part.draft, nullptr);
  std::vector<char> supported(canvas.n_vertices(), 0);
  for (int v : region->draftSupport)
    supported[std::size_t(v)] = 1;
  for (auto v : canvas.vertices())
    EXPECT_EQ(pointOf(part.draft->surface, v), supported[std::size_t(v.idx())]
                                                   ? pointOf(whole.draft->surface, v)
                                                   : pointOf(canvas, v));
}

// The mountain's canvas of the compare graphs onto the shared sphere.
TEST(DpmLift, MountainOntoTheSphere) {
  const MeshPtr mountain = readMesh(test::meshPath("mountain.obj")).mesh;
  const int face = nearestSurfacePoint(mountain->surface, {0.068548, 19.73209, 0.029055}).face;
  const auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(mountain, face, 8));
  const test::NodeRun dpm = test::runNode("geobrush.dpm", {{"canvas", canvas}});
  const auto source = dpm.get<Parameterization>("parameterization");
  ASSERT_NE(source, nullptr);
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const auto target = stamp(sphere, source, {{"origin", Vec3{0.0, 0.0, 1.0}}, {"scale", 0.05}});
  ASSERT_NE(target, nullptr);
  const Lifted lifted = lift(source, target);
  ASSERT_NE(lifted.draft, nullptr);
  EXPECT_TRUE(lifted.warnings.empty());
  ASSERT_EQ(lifted.draft->surface.n_vertices(), canvas->surface.n_vertices());
  EXPECT_EQ(test::faceIndices(lifted.draft->surface), test::faceIndices(canvas->surface));
  for (auto v : canvas->surface.vertices()) {
    const Eigen::Vector3d p = pointOf(lifted.draft->surface, v);
    ASSERT_TRUE(p.allFinite());
    // Its base point X_T = p - lambda h n_PT lies on the (faceted) unit sphere.
    const double h = offsetFromPlane(source->origin, pointOf(canvas->surface, v));
    const Eigen::Vector3d base = p - 0.05 * h * target->origin.normal;
    EXPECT_NEAR(base.norm(), 1, 0.02) << v.idx();
  }
  // Two evaluations: bit-identical drafts.
  EXPECT_EQ(lift(source, target).draft->contentHash(), lifted.draft->contentHash());
}

TEST(DpmLiftNode, NamesThePortOfABadInput) {
  const auto source = bumpSource();
  const auto target = stamp(plane(20, 4), source, {});
  ASSERT_NE(target, nullptr);
  auto where = [](const ParameterizationPtr& s, const ParameterizationPtr& t,
                  const Region2DPtr& region) -> std::string {
    try {
      lift(s, t, {}, region);
    } catch (const NodeError& e) {
      return e.where();
    }
    return "(accepted)";
  };
  const auto empty = std::make_shared<const Parameterization>();
  EXPECT_EQ(where(empty, target, nullptr), "input 'source'");
  EXPECT_EQ(where(source, empty, nullptr), "input 'target'");
  auto bad = std::make_shared<Region2D>();
  bad->draftSupport = {0, int(source->uv.size())};
  EXPECT_EQ(where(source, target, bad), "input 'region'");
  auto shortMap = std::make_shared<Parameterization>(*source);
  shortMap->uv.pop_back();
  EXPECT_EQ(where(shortMap, target, nullptr), "input 'source'");
}

}  // namespace
}  // namespace geobrush
