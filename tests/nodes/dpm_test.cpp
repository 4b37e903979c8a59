#include "geobrush/projective_map.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/surface_point.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

constexpr double kPi = std::numbers::pi;

// A (nu + 1) x (nv + 1) grid of points, two triangles per cell, oriented so that the normal is
// d point / di x d point / dj.
MeshPtr gridMesh(int nu, int nv, const std::function<Eigen::Vector3d(int, int)>& point) {
  TriMesh mesh;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      mesh.add_vertex(toPoint(point(i, j)));
  auto at = [nu](int i, int j) { return TriMesh::VertexHandle(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

// The unit sphere's cap of polar angles up to `maxDegrees` around the pole +z, in `rings` rings
// of `segments` vertices each (ring k at polar angle k maxDegrees / rings).
MeshPtr sphereCap(double maxDegrees, int rings, int segments) {
  TriMesh mesh;
  mesh.add_vertex({0, 0, 1});
  for (int k = 1; k <= rings; ++k)
    for (int m = 0; m < segments; ++m) {
      const double phi = k * maxDegrees / rings * kPi / 180, theta = 2 * kPi * m / segments;
      mesh.add_vertex(
          {std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta), std::cos(phi)});
    }
  auto at = [segments](int k, int m) {
    return TriMesh::VertexHandle(k == 0 ? 0 : 1 + (k - 1) * segments + m % segments);
  };
  for (int m = 0; m < segments; ++m)
    mesh.add_face(at(0, 0), at(1, m), at(1, m + 1));
  for (int k = 1; k < rings; ++k)
    for (int m = 0; m < segments; ++m) {
      mesh.add_face(at(k, m), at(k + 1, m), at(k + 1, m + 1));
      mesh.add_face(at(k, m), at(k + 1, m + 1), at(k, m + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

// The whole mesh as a canvas whose origin is `origin` (on the surface).
CanvasPtr wholeCanvas(const MeshPtr& mesh, const Eigen::Vector3d& origin) {
  std::vector<int> faces(mesh->surface.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  const SurfacePoint at = nearestSurfacePoint(mesh->surface, origin);
  return std::make_shared<const Canvas>(canvasOnFaces(mesh, faces, at.face, origin));
}

ProjectiveMapResult mapOf(const CanvasPtr& canvas, const Eigen::Vector3d& view = {0, 0, 0},
                          double angle = 0, int rings = 3) {
  ProjectiveMapOptions o;
  o.view = view;
  o.angleDegrees = angle;
  o.reversedRing = rings;
  return projectiveMap(canvas, o);
}

// The (u, v) of a plane offset d seen along +z with the axes turned by `degrees`.
Eigen::Vector2d turned(const Eigen::Vector2d& d, double degrees) {
  const double a = degrees * kPi / 180;
  return {std::cos(a) * d.x() + std::sin(a) * d.y(), -std::sin(a) * d.x() + std::cos(a) * d.y()};
}

TEST(ProjectiveMap, PlaneSeenAlongZIsTheIdentity) {
  const MeshPtr plane = gridMesh(
      20, 20, [](int i, int j) { return Eigen::Vector3d(-1 + i / 10.0, -1 + j / 10.0, 0); });
  const CanvasPtr canvas = wholeCanvas(plane, Eigen::Vector3d::Zero());
  for (const Eigen::Vector3d& view : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 0)}) {
    const ProjectiveMapResult map = mapOf(canvas, view);
    ASSERT_EQ(map.uv.size(), canvas->surface.n_vertices());
    EXPECT_EQ(map.origin.normal, Eigen::Vector3d::UnitZ());
    for (auto v : canvas->surface.vertices()) {
      const Eigen::Vector3d p = pointOf(canvas->surface, v);
      EXPECT_EQ(map.uv[std::size_t(v.idx())], Eigen::Vector2d(p.x(), p.y())) << v.idx();
      EXPECT_EQ(map.offset[std::size_t(v.idx())], 0.0);
    }
    // The centre vertex, bit-exact (the paper: "accurately captures the center vertex").
    EXPECT_EQ(map.uv[std::size_t(canvas->originVertex)], Eigen::Vector2d::Zero());
    EXPECT_EQ(std::count(map.reversedFaces.begin(), map.reversedFaces.end(), 1), 0);
  }
}

TEST(ProjectiveMap, TurnedAxesAndAnOriginInsideAFace) {
  const MeshPtr plane =
      gridMesh(16, 16, [](int i, int j) { return Eigen::Vector3d(-1 + i / 8.0, -1 + j / 8.0, 0); });
  const Eigen::Vector3d origin(0.137, -0.211, 0);
  const CanvasPtr canvas = wholeCanvas(plane, origin);
  for (double angle : {30.0, -135.0}) {
    const ProjectiveMapResult map = mapOf(canvas, {0, 0, 2.5}, angle);
    EXPECT_EQ(projectOntoPlane(map.origin, canvas->originPoint), Eigen::Vector2d::Zero());
    for (auto v : canvas->surface.vertices()) {
      const Eigen::Vector3d d = pointOf(canvas->surface, v) - origin;
      EXPECT_LE((map.uv[std::size_t(v.idx())] - turned({d.x(), d.y()}, angle)).norm(), 1e-15);
    }
  }
  // The paper's centre vertex instead of the origin point.
  ProjectiveMapOptions o;
  o.centerAtVertex = true;
  const ProjectiveMapResult atVertex = projectiveMap(canvas, o);
  EXPECT_EQ(atVertex.uv[std::size_t(canvas->originVertex)], Eigen::Vector2d::Zero());
  EXPECT_EQ(atVertex.origin.point, pointOf(canvas->surface, canvas->originVertex));
}

// |uv| = sin(phi), h = cos(phi) - 1 on the unit sphere around the pole.
TEST(ProjectiveMap, SphereCapRadiusIsTheSineOfThePolarAngle) {
  const CanvasPtr canvas = wholeCanvas(sphereCap(80, 16, 32), Eigen::Vector3d::UnitZ());
  const ProjectiveMapResult map = mapOf(canvas);  // the view: the normal at the pole
  EXPECT_LE((map.origin.normal - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  for (auto v : canvas->surface.vertices()) {
    const Eigen::Vector3d p = pointOf(canvas->surface, v);
    const double phi = std::acos(std::clamp(p.z(), -1.0, 1.0));
    EXPECT_NEAR(map.uv[std::size_t(v.idx())].norm(), std::sin(phi), 1e-12) << v.idx();
    EXPECT_NEAR(map.offset[std::size_t(v.idx())], std::cos(phi) - 1, 1e-12) << v.idx();
  }
  EXPECT_EQ(std::count(map.reversedFaces.begin(), map.reversedFaces.end(), 1), 0);
}

// Past the equator the projection folds: exactly the faces below it are reversed, and the rings
// grow the flags upwards.
TEST(ProjectiveMap, CapBeyondTheEquatorIsReversedBelowIt) {
  const CanvasPtr canvas = wholeCanvas(sphereCap(120, 12, 24), Eigen::Vector3d::UnitZ());
  const TriMesh& s = canvas->surface;
  const ProjectiveMapResult exact = mapOf(canvas, {0, 0, 1}, 0, 0);
  std::size_t below = 0;
  for (auto f : s.faces()) {
    double highest = -1;
    for (auto v : s.fv_range(f))
      highest = std::max(highest, pointOf(s, v).z());
    const bool isBelow = highest < 1e-12;
    below += isBelow;
    EXPECT_EQ(exact.reversedFaces[std::size_t(f.idx())] != 0, isBelow) << f.idx();
  }
  EXPECT_EQ(below, 3u * 2 * 24);
  const ProjectiveMapResult grown = mapOf(canvas, {0, 0, 1}, 0, 3);
  EXPECT_EQ(std::count(grown.reversedFaces.begin(), grown.reversedFaces.end(), 1),
            (3 + 3) * 2 * 24);
}

// The cylinder x^2 + z^2 = rho^2 around the y axis, seen along +z: uv = (rho sin psi, y),
// h = rho (cos psi - 1).
TEST(ProjectiveMap, CylinderSeenAcrossItsAxis) {
  const double rho = 0.7, psiMax = kPi / 3;
  auto psiOf = [&](int i) { return -psiMax + 2 * psiMax * i / 24; };
  const MeshPtr cylinder = gridMesh(24, 10, [&](int i, int j) {
    return Eigen::Vector3d(rho * std::sin(psiOf(i)), -1 + j / 5.0, rho * std::cos(psiOf(i)));
  });
  const CanvasPtr canvas = wholeCanvas(cylinder, {0, 0, rho});
  for (const double angle : {0.0, 50.0}) {
    const ProjectiveMapResult map = mapOf(canvas, {0, 0, 1}, angle);
    const ProjectiveMapResult byNormal = mapOf(canvas, {0, 0, 0}, angle);
    for (int j = 0; j <= 10; ++j)
      for (int i = 0; i <= 24; ++i) {
        const std::size_t v = std::size_t(j * 25 + i);
        const Eigen::Vector2d expected = turned({rho * std::sin(psiOf(i)), -1 + j / 5.0}, angle);
        EXPECT_LE((map.uv[v] - expected).norm(), 1e-12) << i << ", " << j;
        EXPECT_NEAR(map.offset[v], rho * (std::cos(psiOf(i)) - 1), 1e-12);
        EXPECT_LE((byNormal.uv[v] - map.uv[v]).norm(), 1e-12);
      }
  }
}

// E2, E3: the decal's disc holds the square [0, 1]^2, its farthest vertex on the circle through
// the square's corners.
TEST(ProjectiveMap, TexelCoordinatesInscribeTheUnitSquare) {
  const CanvasPtr canvas = wholeCanvas(sphereCap(70, 10, 24), Eigen::Vector3d::UnitZ());
  const ProjectiveMapResult map = mapOf(canvas);
  const TexelCoordinates texels = texelCoordinates(map.uv);
  EXPECT_NEAR(texels.radius, std::sin(70 * kPi / 180), 1e-12);
  double farthest = 0;
  for (std::size_t i = 0; i < texels.st.size(); ++i) {
    farthest = std::max(farthest, (texels.st[i] - Eigen::Vector2d(0.5, 0.5)).norm());
    EXPECT_LE((domainOfTexel(texels.st[i], texels.radius) - map.uv[i]).norm(), 1e-15);
  }
  EXPECT_NEAR(farthest, 1 / std::sqrt(2.0), 1e-15);
  // The square's corners lie on the decal's circle.
  EXPECT_NEAR(domainOfTexel({1, 1}, texels.radius).norm(), texels.radius, 1e-15);
  EXPECT_NEAR(domainOfTexel({0, 1}, texels.radius).norm(), texels.radius, 1e-15);
  EXPECT_THROW(texelCoordinates({Eigen::Vector2d::Zero()}), std::invalid_argument);
}

TEST(ProjectiveMap, CropToDiscKeepsTheFacesInsideTheInnerCircle) {
  const MeshPtr plane = gridMesh(
      20, 20, [](int i, int j) { return Eigen::Vector3d(-1 + i / 10.0, -1 + j / 10.0, 0); });
  const CanvasPtr canvas = wholeCanvas(plane, {0.01, 0.02, 0});
  ProjectiveMapOptions o;
  o.cropToDisc = true;
  const ProjectiveMapResult map = projectiveMap(canvas, o);
  const Canvas& cropped = *map.canvas;
  EXPECT_EQ(meshStats(cropped.surface).boundaryLoops, 1u);
  EXPECT_EQ(cropped.source, plane);
  // The disc reaches the outline's nearest vertex.
  double radius = std::numeric_limits<double>::infinity();
  for (int b : canvas->boundary)
    radius = std::min(radius, (pointOf(canvas->surface, b) - canvas->originPoint).norm());
  EXPECT_NEAR(radius, std::hypot(0.01, 0.98), 1e-15);
  ASSERT_EQ(map.uv.size(), cropped.surface.n_vertices());
  std::vector<char> kept(plane->surface.n_faces(), 0);
  for (auto f : cropped.surface.faces())
    kept[std::size_t(cropped.sourceFace[std::size_t(f.idx())])] = 1;
  for (auto v : cropped.surface.vertices()) {
    EXPECT_LE(map.uv[std::size_t(v.idx())].norm(), radius);
    EXPECT_EQ(pointOf(cropped.surface, v),
              pointOf(plane->surface, cropped.sourceVertex[std::size_t(v.idx())]));
  }
  // Every face well inside the disc is kept (at its edge, cutting off pinches may drop some).
  for (auto f : plane->surface.faces()) {
    double farthest = 0;
    for (auto v : plane->surface.fv_range(f))
      farthest = std::max(farthest, (pointOf(plane->surface, v) - cropped.originPoint).norm());
    if (farthest <= radius - 0.15) {
      EXPECT_TRUE(kept[std::size_t(f.idx())]) << f.idx();
    }
  }
}

TEST(ProjectiveMap, RefusesBadInput) {
  auto option = [](const CanvasPtr& canvas, const ProjectiveMapOptions& o) -> std::string {
    try {
      projectiveMap(canvas, o);
    } catch (const ProjectiveMapError& e) {
      return e.option();
    }
    return "(accepted)";
  };
  const CanvasPtr plane =
      wholeCanvas(gridMesh(4, 4, [](int i, int j) { return Eigen::Vector3d(i, j, 0); }), {2, 2, 0});
  ProjectiveMapOptions o;
  EXPECT_EQ(option(std::make_shared<const Canvas>(), o), "canvas");
  EXPECT_EQ(option(nullptr, o), "canvas");
  o.view = {std::nan(""), 0, 1};
  EXPECT_EQ(option(plane, o), "view");
  o = {};
  o.angleDegrees = std::numeric_limits<double>::infinity();
  EXPECT_EQ(option(plane, o), "angle");
  o = {};
  o.reversedRing = -1;
  EXPECT_EQ(option(plane, o), "reversed_ring");
  // An origin on the outline leaves no disc.
  o = {};
  o.cropToDisc = true;
  EXPECT_EQ(
      option(wholeCanvas(gridMesh(4, 4, [](int i, int j) { return Eigen::Vector3d(i, j, 0); }),
                         {0, 2, 0}),
             o),
      "crop_to_disc");
}

using test::DirectContext;

const NodeType& dpmType() {
  const NodeType* type = test::registry().find("geobrush.dpm");
  EXPECT_NE(type, nullptr) << (test::registryLoadErrors().empty() ? ""
                                                                  : test::registryLoadErrors()[0]);
  return *type;
}

ParameterizationPtr runDpm(const CanvasPtr& canvas, const ParamMap& params = {}) {
  DirectContext ctx(dpmType(), {{"canvas", canvas}}, params);
  dpmType().create()->compute(ctx);
  auto out = std::dynamic_pointer_cast<const Parameterization>(ctx.outputs["parameterization"]);
  // One warning, about folds, exactly where faces are flagged reversed.
  const auto folded = std::count(out->reversedFaces.begin(), out->reversedFaces.end(), 1);
  EXPECT_EQ(ctx.warnings.size(), folded > 0 ? 1u : 0u);
  if (folded > 0 && !ctx.warnings.empty()) {
    EXPECT_TRUE(
        test::contains(ctx.warnings[0], std::to_string(folded) + " canvas faces are folded"))
        << ctx.warnings[0];
  }
  return out;
}

// The mountain's canvas of the compare graphs: radius 8 around its peak.
CanvasPtr mountainCanvas() {
  const MeshPtr mesh = readMesh(test::meshPath("mountain.obj")).mesh;
  const int face = nearestSurfacePoint(mesh->surface, {0.068548, 19.73209, 0.029055}).face;
  return std::make_shared<const Canvas>(test::growDiscCanvas(mesh, face, 8));
}

TEST(DpmNode, OutputsTheProjectiveMapOfTheMountain) {
  const CanvasPtr canvas = mountainCanvas();
  const auto out = runDpm(canvas, {{"angle", 25.0}});
  ASSERT_NE(out, nullptr);
  ProjectiveMapOptions o;
  o.angleDegrees = 25;
  const ProjectiveMapResult map = projectiveMap(canvas, o);
  EXPECT_EQ(out->canvas, canvas);
  EXPECT_EQ(out->uv, map.uv);
  EXPECT_EQ(out->reversedFaces, map.reversedFaces);
  EXPECT_EQ(out->origin.vAxis, map.origin.vAxis);
  EXPECT_EQ(out->rotation, 0.0);
  EXPECT_EQ(out->scale, 1.0);
  ASSERT_EQ(out->normal.size(), out->uv.size());
  EXPECT_EQ(out->reversedFaces.size(), canvas->surface.n_faces());
  // The default view: the one under which the canvas shows its largest area, the direction of
  // the sum of its faces' area-weighted normals. The mountain's peak leans (its own normal there is
  // far from it); the canvas as a whole faces up its y axis.
  Eigen::Vector3d vectorArea = Eigen::Vector3d::Zero();
  for (auto f : canvas->surface.faces()) {
    auto v = canvas->surface.cfv_begin(f);
    const Eigen::Vector3d a = pointOf(canvas->surface, *v), b = pointOf(canvas->surface, *++v),
                          c = pointOf(canvas->surface, *++v);
    vectorArea += (b - a).cross(c - a);
  }
  EXPECT_LT((out->origin.normal - vectorArea.normalized()).norm(), 1e-12);
  EXPECT_GT(out->origin.normal.y(), 0.9);
  const Eigen::Vector3d peakNormal =
      surfaceNormalAt(canvas->source->surface, canvas->sourceFace[std::size_t(canvas->originFace)],
                      canvas->originPoint);
  EXPECT_LT(peakNormal.y(), 0.5);
  EXPECT_EQ(runDpm(canvas, {{"view", Vec3{0.0, 2.0, 0.0}}})->origin.normal,
            Eigen::Vector3d::UnitY());
  for (auto v : canvas->surface.vertices()) {
    const std::size_t i = std::size_t(v.idx());
    EXPECT_EQ(out->normal[i], out->origin.normal);
    ASSERT_TRUE(out->uv[i].allFinite());
    // A projection never lengthens.
    EXPECT_LE(out->uv[i].norm(),
              (pointOf(canvas->surface, v) - canvas->originPoint).norm() * (1 + 1e-12));
  }
  EXPECT_EQ(projectOntoPlane(out->origin, canvas->originPoint), Eigen::Vector2d::Zero());
  // Two evaluations: bit-identical values.
  EXPECT_EQ(runDpm(canvas, {{"angle", 25.0}})->contentHash(), out->contentHash());
}

TEST(DpmNode, CropsAndCentresOnTheVertexWhenAsked) {
  const CanvasPtr canvas = mountainCanvas();
  const auto out = runDpm(canvas, {{"crop_to_disc", true}, {"center", std::string("vertex")}});
  ASSERT_NE(out, nullptr);
  EXPECT_LT(out->canvas->surface.n_faces(), canvas->surface.n_faces());
  EXPECT_EQ(out->canvas->source, canvas->source);
  EXPECT_EQ(meshStats(out->canvas->surface).boundaryLoops, 1u);
  EXPECT_EQ(out->uv.size(), out->canvas->surface.n_vertices());
  EXPECT_EQ(out->uv[std::size_t(out->canvas->originVertex)], Eigen::Vector2d::Zero());
}

TEST(DpmNode, NamesThePortOrParamOfABadInput) {
  auto where = [](const CanvasPtr& canvas, const ParamMap& params) -> std::string {
    DirectContext ctx(dpmType(), {{"canvas", canvas}}, params);
    try {
      dpmType().create()->compute(ctx);
    } catch (const NodeError& e) {
      return e.where();
    }
    return "(accepted)";
  };
  EXPECT_EQ(where(std::make_shared<const Canvas>(), {}), "input 'canvas'");
  EXPECT_EQ(where(mountainCanvas(), {{"reversed_ring", std::int64_t{-2}}}),
            "param 'reversed_ring'");
}

}  // namespace
}  // namespace geobrush
