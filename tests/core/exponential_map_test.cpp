#include "geobrush/exponential_map.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

#include "canvas_fixtures.hpp"
#include "geobrush/mesh_io.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

double flat(double, double) {
  return 0;
}

// The face of `mesh` nearest to `p` (by centroid).
int faceNear(const TriMesh& mesh, const Eigen::Vector3d& p) {
  int best = 0;
  double distance = std::numeric_limits<double>::infinity();
  for (auto f : mesh.faces()) {
    const Eigen::Vector3d c = toEigen(mesh.calc_face_centroid(f));
    if ((c - p).norm() < distance) {
      distance = (c - p).norm();
      best = f.idx();
    }
  }
  return best;
}

DemOptions mode(bool generalized) {
  DemOptions o;
  o.generalized = generalized;
  return o;
}

Eigen::Vector3d point(const Canvas& c, int v) {
  return toEigen(c.surface.point(TriMesh::VertexHandle(v)));
}

TEST(ExponentialMap, NearestNeighboursAreExact) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  std::vector<Eigen::Vector3d> points(600);
  for (auto& p : points) {
    // Points on a wavy sheet, plus a few duplicates to exercise the ties.
    p = {coordinate(random), coordinate(random), 0};
    p.z() = 0.2 * std::sin(4 * p.x());
  }
  points.push_back(points[10]);
  points.push_back(points[10]);
  const auto knn = nearestNeighbours(points, 8);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::pair<double, int>> all;
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i) all.push_back({(points[j] - points[i]).squaredNorm(), static_cast<int>(j)});
    std::sort(all.begin(), all.end());
    std::vector<int> expected;
    for (int k = 0; k < 8; ++k)
      expected.push_back(all[k].second);
    EXPECT_EQ(knn[i], expected) << "point " << i;
  }
  EXPECT_EQ(nearestNeighbours({{0, 0, 0}, {1, 0, 0}}, 8),
            (std::vector<std::vector<int>>{{1}, {0}}));
}

// The brute-force k nearest, by (squared distance, index).
std::vector<std::vector<int>> bruteForceNeighbours(const std::vector<Eigen::Vector3d>& points,
                                                   int k) {
  std::vector<std::vector<int>> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::pair<double, int>> all;
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i) all.push_back({(points[j] - points[i]).squaredNorm(), static_cast<int>(j)});
    std::sort(all.begin(), all.end());
    for (int m = 0; m < std::min<int>(k, static_cast<int>(all.size())); ++m)
      result[i].push_back(all[m].second);
  }
  return result;
}

TEST(ExponentialMap, NearestNeighboursAreExactForClustersAndOutliers) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  // A dense blob, a sparse cloud around it and a far line of outliers: the grid's cells then hold
  // very different numbers of points, and the outliers must search many shells.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 400; ++i)
    points.push_back(0.01 * Eigen::Vector3d(coordinate(random), coordinate(random), 0));
  for (int i = 0; i < 200; ++i)
    points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  for (int i = 0; i < 12; ++i)
    points.emplace_back(30 + i, -20, 5);
  for (int k : {1, 8, 25}) {
    SCOPED_TRACE(k);
    const auto expected = bruteForceNeighbours(points, k);
    for (int threads : {1, 3}) {
      EXPECT_EQ(nearestNeighbours(points, k, threads), expected) << threads << " threads";
    }
  }
}

TEST(ExponentialMap, PlaneMapsIsometricallyInBothModes) {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  rigid.pretranslate(Eigen::Vector3d(0.3, -1.2, 2));
  const MeshPtr plane = test::heightGrid(24, flat, rigid);
  const Canvas canvas = test::growDiscCanvas(
      plane, faceNear(plane->surface, rigid * Eigen::Vector3d(0.13, -0.07, 0)), 0.8);
  for (bool generalized : {false, true}) {
    SCOPED_TRACE(generalized ? "generalized" : "original");
    const DemResult dem = discreteExponentialMap(canvas, mode(generalized));
    const auto n = dem.uv.size();
    ASSERT_EQ(n, canvas.surface.n_vertices());
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const double planar = (dem.uv[i] - dem.uv[j]).norm();
        const double spatial = (point(canvas, i) - point(canvas, j)).norm();
        worst = std::max(worst, std::abs(planar - spatial));
      }
    }
    EXPECT_LE(worst, 1e-9);
    EXPECT_LE((dem.origin.normal - rigid.linear() * Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    for (const auto& normal : dem.normal)
      EXPECT_LE((normal - dem.origin.normal).norm(), 1e-12);
    // Orientation is kept: (u, v, normal) is right-handed.
    EXPECT_LE((dem.origin.uAxis.cross(dem.origin.vAxis) - dem.origin.normal).norm(), 1e-12);
    EXPECT_TRUE(std::none_of(dem.reversedFaces.begin(), dem.reversedFaces.end(),
                             [](auto f) { return f != 0; }));
  }
}

TEST(ExponentialMap, AxesFollowGlobalYAndTheAngle) {
  const MeshPtr plane = test::heightGrid(20, flat);
  const Canvas canvas = test::growDiscCanvas(plane, faceNear(plane->surface, {0.12, 0.05, 0}), 0.7);
  const Eigen::Vector3d origin = canvas.originPoint;
  const DemResult straight = discreteExponentialMap(canvas, mode(true));
  // At angle 0 the v axis is +y, so u is +x.
  for (std::size_t i = 0; i < straight.uv.size(); ++i) {
    const Eigen::Vector3d d = point(canvas, i) - origin;
    EXPECT_LE((straight.uv[i] - Eigen::Vector2d(d.x(), d.y())).norm(), 1e-12);
  }
  for (bool generalized : {false, true}) {
    for (double degrees : {30.0, 90.0, -135.0}) {
      DemOptions o = mode(generalized);
      o.angleDegrees = degrees;
      const DemResult turned = discreteExponentialMap(canvas, o);
      const DemResult base = discreteExponentialMap(canvas, mode(generalized));
      // Turning the axes by a turns the map by -a.
      const Eigen::Matrix2d back = Eigen::Rotation2Dd(-degrees * std::numbers::pi / 180).matrix();
      for (std::size_t i = 0; i < base.uv.size(); ++i)
        EXPECT_LE((turned.uv[i] - back * base.uv[i]).norm(), 1e-12) << degrees;
    }
  }
}

TEST(ExponentialMap, EquationOneNormals) {
  // A curved cap: boundary normals are the surface normals, inside they are unit blends.
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  const Canvas canvas = test::growDiscCanvas(sphere, faceNear(sphere->surface, {0, 0, 1}), 1.0);
  const auto surface = surfaceNormals(canvas);
  const auto eq1 = interpolatedNormals(canvas, surface, 1e-3);
  std::vector<char> onBoundary(eq1.size(), 0);
  for (int b : canvas.boundary)
    onBoundary[b] = 1;
  double interiorChange = 0;
  for (std::size_t i = 0; i < eq1.size(); ++i) {
    EXPECT_NEAR(eq1[i].norm(), 1.0, 1e-12);
    if (onBoundary[i]) {
      EXPECT_EQ(eq1[i], surface[i]);
    } else {
      interiorChange = std::max(interiorChange, (eq1[i] - surface[i]).norm());
    }
    // Surface normals of the unit sphere are close to the radial direction.
    EXPECT_GT(surface[i].dot(point(canvas, i).normalized()), 0.99);
  }
  EXPECT_GT(interiorChange, 0.1);
  // The result's normals are Eq. 1's with the default epsilon.
  EXPECT_EQ(discreteExponentialMap(canvas, mode(true)).normal,
            interpolatedNormals(canvas, surface, DemOptions{}.epsilon));
  EXPECT_EQ(discreteExponentialMap(canvas, mode(false)).normal, surface);
}

TEST(ExponentialMap, EquationOneMatchesTheDirectSum) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  // Boundaries of 38 and 41 vertices: the sum's last lanes are partly padding.
  for (double radius : {1.0, 1.1}) {
    const Canvas canvas =
        test::growDiscCanvas(sphere, faceNear(sphere->surface, {0.2, 0, 1}), radius);
    const auto surface = surfaceNormals(canvas);
    Eigen::Vector3d low = point(canvas, 0), high = low;
    for (auto v : canvas.surface.vertices()) {
      low = low.cwiseMin(point(canvas, v.idx()));
      high = high.cwiseMax(point(canvas, v.idx()));
    }
    for (double epsilon : {1e-3, 0.5}) {
      SCOPED_TRACE(testing::Message() << "radius " << radius << " epsilon " << epsilon);
      const double eps = epsilon * (high - low).squaredNorm();
      const auto eq1 = interpolatedNormals(canvas, surface, epsilon);
      double worst = 0;
      for (auto v : canvas.surface.vertices()) {
        if (std::count(canvas.boundary.begin(), canvas.boundary.end(), v.idx())) continue;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int b : canvas.boundary)
          sum += surface[b] / ((point(canvas, b) - point(canvas, v.idx())).squaredNorm() + eps);
        worst = std::max(worst, (eq1[v.idx()] - sum.normalized()).norm());
      }
      // Only the order of the additions differs.
      EXPECT_LE(worst, 1e-14);
    }
  }
}

TEST(ExponentialMap, ResultsDoNotDependOnTheThreadCount) {
  const MeshPtr mesh = readMesh(test::meshPath("armadillo.obj")).mesh;
  const int face =
      mesh->surface.face_handle(mesh->surface.halfedge_handle(TriMesh::VertexHandle(5000))).idx();
  // About 2600 vertices: several blocks of the per-vertex steps.
  const Canvas canvas = test::growDiscCanvas(mesh, face, 0.25);
  for (bool generalized : {true, false}) {
    SCOPED_TRACE(generalized ? "generalized" : "original");
    DemOptions o = mode(generalized);
    o.threads = 1;
    const DemResult one = discreteExponentialMap(canvas, o);
    for (int threads : {2, 3, 8}) {
      o.threads = threads;
      const DemResult many = discreteExponentialMap(canvas, o);
      EXPECT_EQ(many.uv, one.uv) << threads;
      EXPECT_EQ(many.normal, one.normal) << threads;
      EXPECT_EQ(many.reversedFaces, one.reversedFaces) << threads;
    }
  }
}

// Geodesic polar coordinates on the unit sphere around o: r = theta (the angle to o), and the
// azimuth of the great circle's start direction, the projection of p onto o's tangent plane.
// With h the longest edge of sphere.obj (0.165): rescaled chord steps along near-geodesic
// Dijkstra paths keep r within a fraction of h (measured 0.019 = 0.12 h; limit h / 4). The
// azimuth drifts more: frames are transported along Dijkstra paths, which stray up to about an
// edge from the geodesic, so the holonomy error is about K h r (K = 1) in angle, h r^2 <= 1.1 h
// in position at the cap's edge r = 1.05 (measured 0.072 = 0.44 h; limit h / 2).
TEST(ExponentialMap, OriginalDemOnASphereCapFollowsGeodesicPolarCoordinates) {
  const MeshPtr sphere = readMesh(test::meshPath("sphere.obj")).mesh;
  // A chord of 1 is a cap of about 60 degrees.
  const Canvas canvas = test::growDiscCanvas(sphere, faceNear(sphere->surface, {0.3, 0.2, 1}), 1.0);
  const Eigen::Vector3d o = canvas.originPoint.normalized();
  const auto lengths = test::edgeLengths(sphere->surface);
  const double h = *std::max_element(lengths.begin(), lengths.end());
  const DemResult dem = discreteExponentialMap(canvas, mode(false));
  EXPECT_LE((dem.origin.normal - o).norm(), 0.01);
  double worstRadius = 0, worstPosition = 0, farthest = 0;
  for (std::size_t i = 0; i < dem.uv.size(); ++i) {
    const Eigen::Vector3d p = point(canvas, i).normalized();
    const double theta = std::acos(std::clamp(p.dot(o), -1.0, 1.0));
    const Eigen::Vector3d t = p - p.dot(o) * o;
    const double azimuth = std::atan2(t.dot(dem.origin.vAxis), t.dot(dem.origin.uAxis));
    const Eigen::Vector2d polar = theta * Eigen::Vector2d(std::cos(azimuth), std::sin(azimuth));
    worstRadius = std::max(worstRadius, std::abs(dem.uv[i].norm() - theta));
    worstPosition = std::max(worstPosition, (dem.uv[i] - polar).norm());
    farthest = std::max(farthest, theta);
  }
  EXPECT_GT(farthest, 0.9);
  EXPECT_LE(worstRadius, h / 4) << "h " << h;
  EXPECT_LE(worstPosition, h / 2) << "h " << h;
}

// A plane with a tall smooth (C2) bump of radius 0.6 in the middle, exactly flat outside.
double bump(double x, double y) {
  const double s = 1 - (x * x + y * y) / (0.6 * 0.6);
  return s > 0 ? 1.5 * s * s * s : 0.0;
}

TEST(ExponentialMap, GeneralizedMapOfABumpIsOneToOneOnItsBase) {
  const MeshPtr mesh = test::heightGrid(40, bump);
  const Canvas canvas = test::growDiscCanvas(mesh, faceNear(mesh->surface, {-0.62, -0.41, 0}), 10);
  ASSERT_EQ(canvas.surface.n_faces(), mesh->surface.n_faces());
  DemOptions o = mode(true);
  // Steep flanks are flagged with a positive threshold (section 4.5).
  o.reversedThreshold = 0.5;
  o.reversedRing = 0;
  const DemResult dem = discreteExponentialMap(canvas, o);
  EXPECT_TRUE(test::boundaryIsSimple(canvas, dem.uv));
  // The flat boundary makes every Eq. 1 normal +z: the map is the projection onto the plane.
  for (std::size_t i = 0; i < dem.uv.size(); ++i) {
    const Eigen::Vector3d d = point(canvas, i) - canvas.originPoint;
    EXPECT_LE((dem.uv[i] - Eigen::Vector2d(d.x(), d.y())).norm(), 1e-9);
  }
  std::size_t flank = 0;
  for (auto f : canvas.surface.faces()) {
    const Eigen::Vector3d c = toEigen(canvas.surface.calc_face_centroid(f));
    const double r = std::hypot(c.x(), c.y());
    if (dem.reversedFaces[f.idx()]) {
      ++flank;
      EXPECT_LT(r, 0.6) << "face " << f.idx();
      EXPECT_GT(r, 0.05) << "face " << f.idx();
    } else if (r > 0.7) {
      EXPECT_EQ(dem.reversedFaces[f.idx()], 0);
    }
  }
  EXPECT_GT(flank, 0u);
  // The default threshold 0 flags nothing on a height field.
  const DemResult plain = discreteExponentialMap(canvas, mode(true));
  EXPECT_EQ(std::count(plain.reversedFaces.begin(), plain.reversedFaces.end(), 1), 0);

  // Flags grow by the k-ring.
  o.reversedRing = 3;
  const DemResult grown = discreteExponentialMap(canvas, o);
  EXPECT_EQ(grown.reversedFaces, growFaceRing(canvas.surface, dem.reversedFaces, 3));
  EXPECT_GT(std::count(grown.reversedFaces.begin(), grown.reversedFaces.end(), 1),
            std::count(dem.reversedFaces.begin(), dem.reversedFaces.end(), 1));
}

TEST(ExponentialMap, FaceRingsGrowByVertexNeighbourhoods) {
  const MeshPtr mesh = test::heightGrid(10, flat);
  std::vector<std::uint8_t> one(mesh->surface.n_faces(), 0);
  // The lower triangle of cell (5, 5).
  one[2 * (5 * 10 + 5)] = 1;
  EXPECT_EQ(growFaceRing(mesh->surface, one, 0), one);
  const auto ring1 = growFaceRing(mesh->surface, one, 1);
  // Its 3 corners touch 6 faces each; each of its edges is counted twice and itself three
  // times: 18 - 3 * 2 + 1 = 13 faces.
  EXPECT_EQ(std::count(ring1.begin(), ring1.end(), 1), 13);
  const auto ring2 = growFaceRing(mesh->surface, one, 2);
  EXPECT_EQ(growFaceRing(mesh->surface, ring1, 1), ring2);
  for (std::size_t f = 0; f < one.size(); ++f)
    EXPECT_LE(ring1[f], ring2[f]);
}

TEST(ExponentialMap, RealMeshesGiveFiniteMapsWithSimpleBoundaries) {
  for (const auto& [name, vertex, radius] :
       {std::tuple{"armadillo.obj", 5000, 0.06}, std::tuple{"armadillo.obj", 12000, 0.05},
        std::tuple{"bunny_small.obj", 1000, 0.12}}) {
    SCOPED_TRACE(std::string(name) + " vertex " + std::to_string(vertex));
    const MeshPtr mesh = readMesh(test::meshPath(name)).mesh;
    const auto lengths = test::edgeLengths(mesh->surface);
    double diagonal = 0;
    for (auto v : mesh->surface.vertices())
      diagonal = std::max(diagonal, (toEigen(mesh->surface.point(v)) -
                                     toEigen(mesh->surface.point(TriMesh::VertexHandle(0))))
                                        .norm());
    const int face =
        mesh->surface.face_handle(mesh->surface.halfedge_handle(TriMesh::VertexHandle(vertex)))
            .idx();
    const Canvas canvas = test::growDiscCanvas(mesh, face, radius * diagonal);
    ASSERT_EQ(test::topology(canvas.surface).boundaryLoops, 1u);
    for (bool generalized : {true, false}) {
      const DemResult dem = discreteExponentialMap(canvas, mode(generalized));
      for (const auto& uv : dem.uv)
        ASSERT_TRUE(uv.allFinite());
      for (const auto& n : dem.normal)
        EXPECT_NEAR(n.norm(), 1.0, 1e-12);
      EXPECT_TRUE(test::boundaryIsSimple(canvas, dem.uv))
          << (generalized ? "generalized" : "original");
      const DemResult again = discreteExponentialMap(canvas, mode(generalized));
      EXPECT_EQ(dem.uv, again.uv);
      EXPECT_EQ(dem.normal, again.normal);
      EXPECT_EQ(dem.reversedFaces, again.reversedFaces);
    }
  }
}

TEST(ExponentialMap, RejectsBadOptionsAndCanvases) {
  const MeshPtr plane = test::heightGrid(6, flat);
  const Canvas canvas = test::growDiscCanvas(plane, 30, 0.8);
  auto rejected = [&](const DemOptions& o, const Canvas& c) -> std::string {
    try {
      discreteExponentialMap(c, o);
    } catch (const DemError& e) {
      return e.option();
    }
    return "(accepted)";
  };
  DemOptions o;
  o.angleDegrees = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(rejected(o, canvas), "angle");
  o = {};
  o.neighbours = 0;
  EXPECT_EQ(rejected(o, canvas), "neighbours");
  o = {};
  o.epsilon = -1;
  EXPECT_EQ(rejected(o, canvas), "epsilon");
  o = {};
  o.reversedThreshold = std::numeric_limits<double>::infinity();
  EXPECT_EQ(rejected(o, canvas), "reversed_threshold");
  o = {};
  o.reversedRing = -1;
  EXPECT_EQ(rejected(o, canvas), "reversed_ring");
  o = {};
  o.threads = -1;
  EXPECT_EQ(rejected(o, canvas), "threads");
  Canvas bad = canvas;
  bad.originFace = 10000;
  EXPECT_EQ(rejected({}, bad), "canvas");
  bad = canvas;
  bad.boundary.clear();
  EXPECT_EQ(rejected({}, bad), "canvas");
}

}  // namespace
}  // namespace geobrush
