// The geodesic region (topology-free cut and paste, "geodesic walk"): a rigid copy of the base's
// polygon on a plane, a closed one on a developable cylinder, a cap of the geodesic polygon's area
// on a sphere, a one-loop region on a real mesh, and the errors of bad inputs.
#include "geodesic_region.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include "direct_context.hpp"
#include "geobrush/cut_paste.hpp"
#include "geobrush/exponential_map.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;

TriMesh::VertexHandle addVertex(TriMesh& mesh, const Vector3d& p) {
  return mesh.add_vertex(toPoint(p));
}

// The square [0, n]^2 of unit squares, two triangles each (alternating diagonals), facing +z,
// moved by `rigid`.
MeshPtr planeGrid(int n, const Eigen::Isometry3d& rigid) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      addVertex(mesh, rigid * Vector3d(i, j, 0));
  auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool even = (i + j) % 2 == 0;
      mesh.add_face(id(i, j), id(i + 1, j), even ? id(i + 1, j + 1) : id(i, j + 1));
      mesh.add_face(even ? id(i, j) : id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return std::make_shared<const Mesh>(mesh);
}

// A polyhedral cylinder (developable) about the z axis, faces outward.
MeshPtr cylinder(double r, double height, int sides, int rings) {
  TriMesh mesh;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < sides; ++i)
      addVertex(mesh, {r * std::cos(2 * kPi * i / sides), r * std::sin(2 * kPi * i / sides),
                       height * j / rings});
  auto id = [sides](int i, int j) { return TriMesh::VertexHandle(j * sides + i % sides); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < sides; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return std::make_shared<const Mesh>(mesh);
}

// A base following cut_paste.hpp's convention: a planar disc whose vertices 0..m-1 are the
// polygon's corners in boundary order (its boundary halfedges run i -> i + 1), a centre vertex,
// and P^SB with the canvas of the disc itself and uv its xy.
ParameterizationPtr discBase(const std::vector<Vector2d>& polygon) {
  TriMesh disc;
  Vector2d centre = Vector2d::Zero();
  for (const Vector2d& p : polygon) {
    addVertex(disc, {p.x(), p.y(), 0});
    centre += p / double(polygon.size());
  }
  const auto c = addVertex(disc, {centre.x(), centre.y(), 0});
  const int m = int(polygon.size());
  for (int i = 0; i < m; ++i)
    disc.add_face(TriMesh::VertexHandle((i + 1) % m), TriMesh::VertexHandle(i), c);
  auto base = std::make_shared<Parameterization>();
  base->canvas = std::make_shared<const Canvas>(canvasOfMesh(std::make_shared<const Mesh>(disc)));
  for (auto v : disc.vertices()) {
    base->uv.push_back(pointOf(disc, v).head<2>());
    base->normal.push_back(Vector3d::UnitZ());
  }
  return base;
}

// A target DEM's placement as dem makes it: the origin snapped, the frame from the target's
// vertex normals turned by `angle` degrees, the scale lambda.
ParameterizationPtr placementOn(const MeshPtr& target, const Vector3d& origin, double angle,
                                double scale) {
  const SurfacePoint snapped = nearestSurfacePoint(target->surface, origin);
  const auto normals = vertexNormals(target->surface);
  std::array<Vector3d, 3> corners, cornerNormals;
  int i = 0;
  for (auto v : target->surface.fv_range(TriMesh::FaceHandle(snapped.face))) {
    corners[std::size_t(i)] = pointOf(target->surface, v);
    cornerNormals[std::size_t(i++)] = normals[std::size_t(v.idx())];
  }
  auto canvas = std::make_shared<Canvas>();
  canvas->source = target;
  auto placement = std::make_shared<Parameterization>();
  placement->canvas = canvas;
  placement->origin = originFrame(corners, cornerNormals, snapped.point, angle);
  placement->rotation = angle * kPi / 180;
  placement->scale = scale;
  return placement;
}

const std::vector<Vector2d> kPentagon = {
    {1.1, 0.2}, {0.5, 1.4}, {-0.9, 1.0}, {-1.2, -0.6}, {0.3, -1.3}};

std::vector<Vector2d> reversed(std::vector<Vector2d> polygon) {
  std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

double perimeter(const std::vector<Vector2d>& polygon) {
  double sum = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    sum += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
  return sum;
}

double cross2(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

bool strictlyInside(const std::vector<Vector2d>& polygon, const Vector2d& x) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vector2d &a = polygon[i], &b = polygon[j];
    if ((a.y() > x.y()) != (b.y() > x.y()) &&
        x.x() < (b.x() - a.x()) * (x.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

bool properlyCross(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d) {
  return cross2(b - a, c - a) * cross2(b - a, d - a) < 0 &&
         cross2(d - c, a - c) * cross2(d - c, b - c) < 0;
}

// Whether a triangle and a polygon overlap in an area (for corners in general position).
bool overlap(const std::array<Vector2d, 3>& t, const std::vector<Vector2d>& polygon) {
  const std::vector<Vector2d> triangle(t.begin(), t.end());
  for (const Vector2d& x : t)
    if (strictlyInside(polygon, x)) return true;
  for (const Vector2d& x : polygon)
    if (strictlyInside(triangle, x)) return true;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < polygon.size(); ++j)
      if (properlyCross(t[i], t[(i + 1) % 3], polygon[j], polygon[(j + 1) % polygon.size()]))
        return true;
  return false;
}

struct RegionOutputs {
  std::shared_ptr<const Canvas> region;
  std::shared_ptr<const SurfacePath> path;
  std::shared_ptr<const Metrics> report;
  std::vector<std::string> warnings;
};

RegionOutputs runNode(const MeshPtr& target, const ParameterizationPtr& base,
                      const ParameterizationPtr& placement) {
  const NodeType* type = test::registry().find("geobrush.geodesic_region");
  EXPECT_NE(type, nullptr);
  test::DirectContext ctx(*type, {{"target", target}, {"base", base}, {"placement", placement}});
  test::run(type->create(), ctx);
  return {std::dynamic_pointer_cast<const Canvas>(ctx.outputs["region"]),
          std::dynamic_pointer_cast<const SurfacePath>(ctx.outputs["path"]),
          std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]), ctx.warnings};
}

// The message of the node's failure, with where it points.
std::string nodeError(const MeshPtr& target, const ParameterizationPtr& base,
                      const ParameterizationPtr& placement) {
  try {
    runNode(target, base, placement);
  } catch (const NodeError& e) {
    return e.where() + ": " + e.what();
  }
  return "no error";
}

std::set<int> regionFaces(const Canvas& region) {
  return {region.sourceFace.begin(), region.sourceFace.end()};
}

double longestEdge(const TriMesh& mesh) {
  double longest = 0;
  for (auto e : mesh.edges())
    longest = std::max(longest, mesh.calc_edge_length(e));
  return longest;
}

double regionArea(const Canvas& region) {
  return test::surfaceArea(region.surface);
}

void expectOneLoopDisc(const Canvas& region) {
  const test::Topology t = test::topology(region.surface);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);
  EXPECT_EQ(t.eulerCharacteristic, 1);
}

}  // namespace

// On a plane the walk is the domain's polygon moved rigidly: corner i at origin + lambda (u_i
// uAxis + v_i vAxis), the frame's axes turned by the angle; the region is exactly the faces the
// polygon overlaps, whichever way the polygon runs.
TEST(GeodesicRegion, IsARigidCopyOfThePolygonOnAPlane) {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.6, Vector3d(2, -1, 3).normalized()));
  rigid.translate(Vector3d(1.5, 0.5, -2));
  const MeshPtr target = planeGrid(16, rigid);
  const double lambda = 2.1;
  const auto placement = placementOn(target, rigid * Vector3d(8.31, 7.77, 0), 30.0, lambda);
  const Frame& frame = placement->origin;
  for (const auto& polygon : {kPentagon, reversed(kPentagon)}) {
    const RegionOutputs run = runNode(target, discBase(polygon), placement);
    ASSERT_TRUE(run.region && run.path && run.report);
    const double length = lambda * perimeter(polygon);
    ASSERT_EQ(run.path->point.size(), polygon.size());
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Vector3d expected =
          frame.point + lambda * (polygon[i].x() * frame.uAxis + polygon[i].y() * frame.vAxis);
      EXPECT_LT((run.path->point[i] - expected).norm(), 1e-12 * length) << i;
    }
    EXPECT_LT(run.path->closingGap, 1e-12 * length);
    EXPECT_EQ(run.path->scale, lambda);
    EXPECT_EQ(run.path->mesh, target);
    EXPECT_TRUE(run.warnings.empty());
    // The faces the polygon overlaps, in the plane's own coordinates.
    std::vector<Vector2d> inPlane;
    for (const Vector2d& p : polygon)
      inPlane.push_back(
          (rigid.inverse() * (frame.point + lambda * (p.x() * frame.uAxis + p.y() * frame.vAxis)))
              .head<2>());
    std::set<int> expected;
    for (auto f : target->surface.faces()) {
      std::array<Vector2d, 3> t;
      int k = 0;
      for (auto v : target->surface.fv_range(f))
        t[std::size_t(k++)] = (rigid.inverse() * pointOf(target->surface, v)).head<2>();
      if (overlap(t, inPlane)) expected.insert(f.idx());
    }
    EXPECT_EQ(regionFaces(*run.region), expected);
    expectOneLoopDisc(*run.region);
    EXPECT_EQ(run.report->values.at("faces"), double(expected.size()));
    EXPECT_LT(run.report->values.at("closing_gap_relative"), 1e-12);
  }
}

// A cylinder unfolds onto the plane: the walk closes up to rounding, and the region's area is the
// polygon's lambda^2 A plus the crossed faces' parts outside it (within an edge of the loop).
TEST(GeodesicRegion, ClosesOnACylinder) {
  const MeshPtr target = cylinder(3.0, 12.0, 48, 24);
  const double lambda = 1.3;
  for (double angle : {0.0, 50.0}) {
    const auto placement = placementOn(target, Vector3d(2.2, 2.1, 5.9), angle, lambda);
    const GeodesicRegionResult result = geodesicRegion(target, *discBase(kPentagon), *placement);
    const double length = lambda * perimeter(kPentagon);
    EXPECT_LT(result.loop.gap, 1e-12 * length) << angle;
    expectOneLoopDisc(result.region);
    const double area = lambda * lambda * signedArea2(kPentagon) / 2;
    EXPECT_GT(regionArea(result.region), area);
    EXPECT_LT(regionArea(result.region), area + length * longestEdge(target->surface));
  }
}

namespace {

// The geodesic regular polygon of m corners, sides s and turns 2 pi / m on the unit sphere, its
// last side closing it (the walk overshoots by its curvature): the corners lie on a small circle
// of polar angle beta, spaced by omega, where the right triangle (centre, corner, mid-side) gives
// cos(omega / 2) = cos(s / 2) cos(pi / m) and sin(beta) = sin(s / 2) / sin(omega / 2) (Napier);
// its area is the sum of the excesses of the triangles from the centre to each side.
double geodesicPolygonArea(int m, double s) {
  const double omega = 2 * std::acos(std::cos(s / 2) * std::cos(kPi / m));
  const double beta = std::asin(std::sin(s / 2) / std::sin(omega / 2));
  auto corner = [&](int k) -> Vector3d {
    return {std::sin(beta) * std::cos(k * omega), std::sin(beta) * std::sin(k * omega),
            std::cos(beta)};
  };
  const Vector3d c = Vector3d::UnitZ();
  double area = 0;
  for (int k = 0; k < m; ++k) {
    const Vector3d a = corner(k), b = corner((k + 1) % m);
    area += 2 * std::atan2(std::abs(c.dot(a.cross(b))), 1 + c.dot(a) + a.dot(b) + b.dot(c));
  }
  return area;
}

std::vector<Vector2d> regularPolygon(int m, double radius) {
  std::vector<Vector2d> polygon;
  for (int k = 0; k < m; ++k)
    polygon.emplace_back(radius * std::cos(2 * kPi * k / m + 0.1),
                         radius * std::sin(2 * kPi * k / m + 0.1));
  return polygon;
}

double enclosedArea(const TriMesh& mesh, const std::vector<int>& faces) {
  double area = 0;
  for (int f : faces) {
    std::array<Vector3d, 3> t;
    int k = 0;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      t[std::size_t(k++)] = pointOf(mesh, v);
    area += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
  }
  return area;
}

}  // namespace

// A regular 16-gon of radius 0.3 walked on the unit icosphere. Walked as it is, its turns
// overshoot (its gap is about rho^2 / 2 of its length: the heading comes back turned by the
// curvature enclosed); closed by a uniform bend, the loop's total turning is 2 pi + bend L, so
// by Gauss-Bonnet it encloses the area A_loop = -bend L on the unit sphere: close to the
// geodesic regular polygon's area A (spherical geometry, above), and closer on the finer mesh.
// A_loop lies between the faces enclosed and the whole region; the crossed faces reach at most
// one longest edge h beyond the loop, so the region exceeds it by less than L h, and the band of
// crossed faces narrows with h.
TEST(GeodesicRegion, IsACapOfTheGeodesicPolygonsAreaOnASphere) {
  const int m = 16;
  const auto polygon = regularPolygon(m, 0.3);
  const double area = geodesicPolygonArea(m, (polygon[1] - polygon[0]).norm());
  std::vector<double> band, areaError;
  for (int level : {4, 5}) {
    const MeshPtr target = std::make_shared<const Mesh>(test::icosphere(level));
    const auto placement = placementOn(target, Vector3d(0.3, 0.8, 0.5), 20.0, 1.0);
    const GeodesicRegionResult result = geodesicRegion(target, *discBase(polygon), *placement);
    expectOneLoopDisc(result.region);
    const double loopArea = -result.loop.bend * result.loop.length;
    const double inside = enclosedArea(target->surface, result.enclosed);
    const double region = regionArea(result.region);
    EXPECT_LT(inside, loopArea) << level;
    EXPECT_GT(region, loopArea) << level;
    EXPECT_LT(region, loopArea + result.loop.length * longestEdge(target->surface)) << level;
    EXPECT_NEAR(result.loop.gap / result.loop.length, 0.3 * 0.3 / 2, 0.01) << level;
    EXPECT_LT(result.loop.stretch.norm(), 0.02) << level;
    band.push_back(region - inside);
    areaError.push_back(std::abs(loopArea - area));
  }
  EXPECT_LT(band[1], 0.6 * band[0]);
  EXPECT_LT(areaError[1], areaError[0]);
  EXPECT_LT(areaError[1], 0.05 * area);
}

// On a real mesh, placed by the target DEM node: a one-loop region around the origin, a small
// gap, the path's corners on their faces.
TEST(GeodesicRegion, PlacesARegionOnTheBunny) {
  const MeshPtr target = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto base = discBase(regularPolygon(12, 0.6));
  const NodeType* dem = test::registry().find("geobrush.dem");
  ASSERT_NE(dem, nullptr);
  const auto& p = target->surface.point(TriMesh::VertexHandle(100));
  test::DirectContext demCtx(*dem, {{"mesh", target}, {"source", base}},
                             {{"origin", Vec3{p[0], p[1], p[2]}}, {"angle", 15.0}});
  test::run(dem->create(), demCtx);
  const auto placement =
      std::dynamic_pointer_cast<const Parameterization>(demCtx.outputs["parameterization"]);
  ASSERT_NE(placement, nullptr);
  const RegionOutputs run = runNode(target, base, placement);
  expectOneLoopDisc(*run.region);
  EXPECT_TRUE(run.warnings.empty());
  const double relative = run.report->values.at("closing_gap_relative");
  EXPECT_LT(relative, 0.05);
  EXPECT_GT(run.report->values.at("faces"), run.report->values.at("crossed_faces"));
  ASSERT_EQ(run.path->point.size(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    const SurfacePoint on = nearestSurfacePoint(target->surface, run.path->point[i]);
    EXPECT_LT(on.distance, 1e-12 * boundingDiagonal(target->surface));
    EXPECT_TRUE(regionFaces(*run.region).count(run.path->face[i])) << i;
  }
}

TEST(GeodesicRegion, RefusesBadInputs) {
  const MeshPtr target = planeGrid(10, Eigen::Isometry3d::Identity());
  const auto base = discBase(kPentagon);
  const auto good = placementOn(target, Vector3d(5.2, 4.9, 0), 0.0, 1.0);
  // Made on another mesh.
  const MeshPtr other = planeGrid(11, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(
      test::contains(nodeError(target, base, placementOn(other, Vector3d(5.2, 4.9, 0), 0, 1)),
                     "input 'placement': the placement was made on another mesh"));
  // So large that the walk runs off the plane.
  EXPECT_TRUE(
      test::contains(nodeError(target, base, placementOn(target, Vector3d(5.2, 4.9, 0), 0, 4)),
                     "input 'placement': the walk on side"));
  // An origin far from the surface.
  auto far = std::make_shared<Parameterization>(*good);
  far->origin.point.z() = 3;
  EXPECT_TRUE(test::contains(nodeError(target, base, far), "input 'placement': the origin lies 3"));
  // A base whose boundary crosses itself in uv.
  EXPECT_TRUE(test::contains(
      nodeError(target, discBase({{1, 0}, {0, 1}, {0, -1}, {-1, 0.2}, {-0.5, 1.5}}), good),
      "input 'base': the base's boundary crosses itself in uv"));
  // A loop wrapped round a small sphere takes all of it or touches itself.
  const MeshPtr ball = std::make_shared<const Mesh>(test::icosphere(3));
  const std::string wrapped = nodeError(ball, discBase(regularPolygon(8, 1.0)),
                                        placementOn(ball, Vector3d(0, 0, 1), 0, 2.5));
  EXPECT_TRUE(test::contains(wrapped, "input 'placement'"));
}

// A flat polygon walked on a sphere at radius 0.45 misses closing by about rho^2 / 2 of its
// length: over the 5% the node warns about.
TEST(GeodesicRegion, WarnsAboutALargeClosingGap) {
  const MeshPtr target = std::make_shared<const Mesh>(test::icosphere(4));
  const RegionOutputs run = runNode(target, discBase(regularPolygon(8, 0.45)),
                                    placementOn(target, Vector3d(0.2, 0.1, 1), 0.0, 1.0));
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(run.warnings[0], "misses closing by"));
  EXPECT_GT(run.report->values.at("closing_gap_relative"), 0.05);
  expectOneLoopDisc(*run.region);
}

}  // namespace geobrush
