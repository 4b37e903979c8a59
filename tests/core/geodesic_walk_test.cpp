// Straightest geodesics (Polthier-Schmies) against analytic cases: straight lines on planes,
// closed squares on a developable cylinder, great circles and Gauss-Bonnet on a sphere, the
// half-angle rule at cone apices, and stops at a boundary.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "geobrush/geodesic_walk.hpp"
#include "geobrush/surface_point.hpp"
#include "mesh_checks.hpp"

using namespace geobrush;

namespace {

using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;

TriMesh::VertexHandle addVertex(TriMesh& mesh, const Vector3d& p) {
  return mesh.add_vertex(toPoint(p));
}

// The square [0, n]^2 cut into unit squares of two triangles each (alternating diagonals), facing
// +z, then moved by `rigid`.
TriMesh planeGrid(int n, const Eigen::Isometry3d& rigid = Eigen::Isometry3d::Identity()) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      addVertex(mesh, rigid * Vector3d(i, j, 0));
  auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        mesh.add_face(id(i, j), id(i + 1, j), id(i, j + 1));
        mesh.add_face(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  return mesh;
}

// A polyhedral cylinder (a prism's side, developable): `sides` vertices around the z axis on each
// of `rings` + 1 rings of radius r, from z = 0 to z = height, faces outward.
TriMesh cylinder(double r, double height, int sides, int rings) {
  TriMesh mesh;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < sides; ++i) {
      const double a = 2 * kPi * i / sides;
      addVertex(mesh, {r * std::cos(a), r * std::sin(a), height * j / rings});
    }
  auto id = [sides](int i, int j) { return TriMesh::VertexHandle(j * sides + (i % sides)); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < sides; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh;
}

// A regular pyramid without its base: apex (vertex 0) at height h over `sides` base corners on
// the unit circle, faces outward. Face k has corners apex, base k, base k + 1.
TriMesh pyramid(int sides, double h) {
  TriMesh mesh;
  addVertex(mesh, {0, 0, h});
  for (int k = 0; k < sides; ++k)
    addVertex(mesh, {std::cos(2 * kPi * k / sides), std::sin(2 * kPi * k / sides), 0});
  for (int k = 0; k < sides; ++k)
    mesh.add_face(TriMesh::VertexHandle(0), TriMesh::VertexHandle(1 + k),
                  TriMesh::VertexHandle(1 + (k + 1) % sides));
  return mesh;
}

// The icosphere of radius r.
TriMesh sphere(int levels, double r) {
  TriMesh mesh = test::icosphere(levels);
  for (auto v : mesh.vertices())
    mesh.set_point(v, mesh.point(v) * r);
  return mesh;
}

double longestEdge(const TriMesh& mesh) {
  double longest = 0;
  for (auto e : mesh.edges())
    longest = std::max(longest, mesh.calc_edge_length(e));
  return longest;
}

// Consecutive faces of a walk share an edge, or a vertex where it passed through one.
void expectConnected(const TriMesh& mesh, const GeodesicWalkResult& walk) {
  ASSERT_EQ(walk.points.size(), walk.faces.size() + 1);
  for (std::size_t i = 0; i + 1 < walk.faces.size(); ++i) {
    int shared = 0;
    for (auto a : mesh.fv_range(TriMesh::FaceHandle(walk.faces[i])))
      for (auto b : mesh.fv_range(TriMesh::FaceHandle(walk.faces[i + 1])))
        shared += a == b;
    EXPECT_GE(shared, 1) << i;
  }
}

struct Walked {
  Vector3d point, direction;
  int face;
};

// Walks the sides of a polygon: `lengths[i]`, then a turn by `turns[i]` (none after the last).
Walked walkPolygon(const TriMesh& mesh, int face, const Vector3d& start, Vector3d direction,
                   const std::vector<double>& lengths, const std::vector<double>& turns) {
  Walked w{start, direction, face};
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    const GeodesicWalkResult leg = walkStraightest(mesh, w.face, w.point, w.direction, lengths[i]);
    EXPECT_EQ(leg.stop, WalkStop::Completed) << i;
    w = {leg.point, leg.direction, leg.face};
    if (i < turns.size()) w.direction = rotateInFace(mesh, w.face, w.direction, turns[i]);
  }
  return w;
}

// The spherical excess of the triangle of unit vectors a, b, c (Van Oosterom-Strackee).
double sphericalExcess(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  return 2 * std::atan2(std::abs(a.dot(b.cross(c))), 1 + a.dot(b) + b.dot(c) + c.dot(a));
}

// At corner b of a great-circle path a -> b -> c on the unit sphere: the turn from the arriving
// to the leaving direction, counter-clockwise about the outward normal b.
double exteriorAngle(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d arriving = b.cross(a.cross(b)).normalized() * -1;  // tangent at b, away from a
  const Vector3d leaving = (c - c.dot(b) * b).normalized();
  return std::atan2(b.dot(arriving.cross(leaving)), arriving.dot(leaving));
}

}  // namespace

TEST(GeodesicWalk, IsAStraightSegmentOnAPlane) {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.rotate(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()));
  rigid.translate(Vector3d(0.3, -1.2, 2.5));
  const TriMesh mesh = planeGrid(12, rigid);
  const Vector3d u = rigid.linear() * Vector3d::UnitX(), v = rigid.linear() * Vector3d::UnitY();
  const SurfacePoint start = nearestSurfacePoint(mesh, rigid * Vector3d(5.37, 4.81, 0));
  for (double angle : {0.1, 0.9, 2.3, 3.3, 4.4, 5.9}) {
    const Vector3d d = std::cos(angle) * u + std::sin(angle) * v;
    const double length = 4.3;
    const GeodesicWalkResult walk = walkStraightest(mesh, start.face, start.point, d, length);
    EXPECT_EQ(walk.stop, WalkStop::Completed);
    EXPECT_EQ(walk.length, length);
    EXPECT_LT((walk.point - (start.point + length * d)).norm(), 1e-12 * length) << angle;
    EXPECT_LT((walk.direction - d).norm(), 1e-12) << angle;
    EXPECT_GT(walk.faces.size(), 4u);
    expectConnected(mesh, walk);
    // Every piece lies on the segment.
    for (const Vector3d& p : walk.points)
      EXPECT_LT((p - start.point).cross(d).norm(), 1e-12 * length);
    // The barycentric coordinates give back the end point.
    Vector3d q = Vector3d::Zero();
    int i = 0;
    for (auto c : mesh.fv_range(TriMesh::FaceHandle(walk.face)))
      q += walk.barycentric[i++] * pointOf(mesh, c.idx());
    EXPECT_LT((q - walk.point).norm(), 1e-12 * length);
  }
}

// Along the grid's diagonals the walk meets vertex after vertex; on a plane each has 2 pi around
// it, and half of it on either side is straight on.
TEST(GeodesicWalk, GoesStraightThroughVerticesOfAPlane) {
  const TriMesh mesh = planeGrid(10);
  const Vector3d d = Vector3d(1, 1, 0).normalized();
  const Vector3d p(2.25, 2.25, 0);
  const SurfacePoint start = nearestSurfacePoint(mesh, p);
  const double length = 5 * std::sqrt(2.0);
  const GeodesicWalkResult walk = walkStraightest(mesh, start.face, p, d, length);
  EXPECT_EQ(walk.stop, WalkStop::Completed);
  EXPECT_EQ(walk.vertices, 5);  // (3,3) .. (7,7)
  EXPECT_LT((walk.point - (p + length * d)).norm(), 1e-12 * length);
  expectConnected(mesh, walk);
  // Starting at a vertex, in a direction outside the start face's corner.
  const int vertex = 3 * 11 + 3;
  int face = -1;
  for (auto f : mesh.vf_range(TriMesh::VertexHandle(vertex)))
    face = f.idx();
  const Vector3d w = Vector3d(-2, 1, 0).normalized();
  const GeodesicWalkResult fromVertex = walkStraightest(mesh, face, pointOf(mesh, vertex), w, 2.0);
  EXPECT_EQ(fromVertex.stop, WalkStop::Completed);
  EXPECT_LT((fromVertex.point - (pointOf(mesh, vertex) + 2.0 * w)).norm(), 1e-12 * 2);
}

// A developable surface unfolds onto the plane: the square's four sides and four turns of pi / 2
// come back to the start, heading as they left, up to rounding.
TEST(GeodesicWalk, ClosesASquareOnACylinder) {
  const TriMesh mesh = cylinder(1.0, 8.0, 24, 20);
  const SurfacePoint start = nearestSurfacePoint(mesh, Vector3d(0.9, 0.5, 4.1));
  const Vector3d n = faceUnitNormal(mesh, start.face);
  for (double heading : {0.3, 1.1, 2.0}) {
    // The tangent direction at `heading` from the cylinder's axis.
    const Vector3d axis = Vector3d::UnitZ();
    const Vector3d d = std::cos(heading) * axis + std::sin(heading) * n.cross(axis);
    const double s = 1.7;
    const Walked end = walkPolygon(mesh, start.face, start.point, d, {s, s, s, s},
                                   {kPi / 2, kPi / 2, kPi / 2, kPi / 2});
    EXPECT_LT((end.point - start.point).norm(), 1e-12 * 4 * s) << heading;
    EXPECT_LT((end.direction - d).norm(), 1e-12) << heading;
  }
}

// Coming up a face's altitude to the apex of a regular pyramid, the half-angle rule leaves along
// the altitude of the opposite face (six sides) or along the opposite edge (five).
TEST(GeodesicWalk, SplitsTheAngleAtAConeApexInHalf) {
  for (int sides : {6, 5}) {
    const TriMesh mesh = pyramid(sides, 0.8);
    const Vector3d apex = pointOf(mesh, 0);
    auto baseMidpoint = [&](int k) -> Vector3d {
      return 0.5 * (pointOf(mesh, 1 + k) + pointOf(mesh, 1 + (k + 1) % sides));
    };
    const Vector3d from = apex + 0.6 * (baseMidpoint(0) - apex);
    const Vector3d d = (apex - from).normalized();
    const double toApex = (apex - from).norm(), beyond = 0.3;
    const GeodesicWalkResult walk = walkStraightest(mesh, 0, from, d, toApex + beyond);
    EXPECT_EQ(walk.stop, WalkStop::Completed);
    EXPECT_EQ(walk.vertices, 1);
    const Vector3d away = sides == 6 ? baseMidpoint(3) - apex : pointOf(mesh, 1 + 3) - apex;
    EXPECT_LT((walk.point - (apex + beyond * away.normalized())).norm(), 1e-12) << sides;
    if (sides == 6) {
      EXPECT_EQ(walk.face, 3);
    }
  }
}

TEST(GeodesicWalk, StopsAtABoundary) {
  const TriMesh mesh = planeGrid(4);
  const Vector3d p(1.3, 2.2, 0), d = Vector3d(2, -1, 0).normalized();
  const SurfacePoint start = nearestSurfacePoint(mesh, p);
  const GeodesicWalkResult walk = walkStraightest(mesh, start.face, p, d, 10.0);
  EXPECT_EQ(walk.stop, WalkStop::Boundary);
  // The line meets x = 4 after (4 - 1.3) / d.x.
  const double reach = 2.7 / d.x();
  EXPECT_NEAR(walk.length, reach, 1e-12);
  EXPECT_LT((walk.point - (p + reach * d)).norm(), 1e-12);
  // Through a boundary vertex: the corner (4, 0).
  const Vector3d q(3, 1, 0), e = Vector3d(1, -1, 0).normalized();
  const SurfacePoint s = nearestSurfacePoint(mesh, q);
  const GeodesicWalkResult corner = walkStraightest(mesh, s.face, q, e, 10.0);
  EXPECT_EQ(corner.stop, WalkStop::Boundary);
  EXPECT_LT((corner.point - Vector3d(4, 0, 0)).norm(), 1e-12);
}

TEST(GeodesicWalk, IsBoundedByItsFaceBudget) {
  const TriMesh mesh = cylinder(1.0, 2.0, 12, 4);
  GeodesicWalkOptions options;
  // Around the cylinder's waist, a closed geodesic, 100 times.
  const double length = 100 * 2 * kPi;
  EXPECT_EQ(walkFaceBudget(mesh, length, options),
            int(mesh.n_faces()) + 16 * int(std::ceil(length / meanEdgeLength(mesh))) + 16);
  options.maxFaces = 50;
  EXPECT_EQ(walkFaceBudget(mesh, length, options), 50);
  const SurfacePoint start = nearestSurfacePoint(mesh, Vector3d(1, 0.1, 1.1));
  const Vector3d d = faceUnitNormal(mesh, start.face).cross(Vector3d::UnitZ());
  const GeodesicWalkResult walk =
      walkStraightest(mesh, start.face, start.point, d, length, options);
  EXPECT_EQ(walk.stop, WalkStop::FaceLimit);
  EXPECT_EQ(walk.faces.size(), 50u);
  EXPECT_LT(walk.length, length);
  EXPECT_THROW(walkStraightest(mesh, -1, start.point, d, 1.0), std::invalid_argument);
  EXPECT_THROW(
      walkStraightest(mesh, start.face, start.point, faceUnitNormal(mesh, start.face), 1.0),
      std::invalid_argument);
  EXPECT_THROW(walkStraightest(mesh, start.face, start.point, d, -1.0), std::invalid_argument);
}

TEST(GeodesicWalk, RotatesInAFacesPlane) {
  const TriMesh mesh = planeGrid(2);
  const Vector3d turned = rotateInFace(mesh, 0, Vector3d(2, 0, 5), kPi / 2);
  EXPECT_LT((turned - Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_LT(
      (rotateInFace(mesh, 0, Vector3d::UnitX(), -kPi / 3) - Vector3d(0.5, -std::sqrt(3.0) / 2, 0))
          .norm(),
      1e-15);
}

namespace {

struct SphereErrors {
  double subtended = 0;  // the largest |angle - d / r| over the straight walks
  double defect = 0;     // |heading defect - area / r^2| of the geodesic triangle
  double gap = 0;        // how far the triangle misses closing, over r
  double edge = 0;       // the longest edge, over r
  double perimeter = 0;  // the triangle's, over r
};

SphereErrors sphereErrors(int levels) {
  const double r = 2.0;
  const TriMesh mesh = sphere(levels, r);
  SphereErrors errors;
  errors.edge = longestEdge(mesh) / r;
  // Straight walks of length d = 2 r from scattered points in scattered directions.
  for (int i = 0; i < 8; ++i) {
    const Vector3d p =
        r * Vector3d(std::cos(1.3 * i + 0.2), std::sin(2.1 * i + 0.5), std::cos(0.7 * i + 1.1))
                .normalized();
    const SurfacePoint start = nearestSurfacePoint(mesh, p);
    const Vector3d n = faceUnitNormal(mesh, start.face);
    const Vector3d d = rotateInFace(mesh, start.face, n.unitOrthogonal(), 0.9 * i);
    const double length = 2 * r;
    const GeodesicWalkResult walk = walkStraightest(mesh, start.face, start.point, d, length);
    EXPECT_EQ(walk.stop, WalkStop::Completed);
    const double angle =
        std::acos(std::clamp(walk.point.normalized().dot(start.point.normalized()), -1.0, 1.0));
    errors.subtended = std::max(errors.subtended, std::abs(angle - length / r));
  }
  // A geodesic triangle: its corners on the sphere, its sides great-circle arcs.
  const Vector3d a = Vector3d(1, 0.2, 0.1).normalized(), b = Vector3d(0.4, 1, 0.3).normalized(),
                 c = Vector3d(0.5, 0.3, 1).normalized();
  auto arc = [](const Vector3d& x, const Vector3d& y) { return std::acos(x.dot(y)); };
  const SurfacePoint start = nearestSurfacePoint(mesh, r * a);
  const Vector3d toward = rotateInFace(mesh, start.face, b - b.dot(a) * a, 0);
  const Walked end = walkPolygon(mesh, start.face, start.point, toward,
                                 {r * arc(a, b), r * arc(b, c), r * arc(c, a)},
                                 {exteriorAngle(a, b, c), exteriorAngle(b, c, a)});
  const Vector3d normal = start.point.normalized();
  auto tangent = [&](const Vector3d& x) { return (x - x.dot(normal) * normal).normalized(); };
  const Vector3d arrive = tangent(end.direction), leave = tangent(toward);
  const double turnAtStart = std::atan2(normal.dot(arrive.cross(leave)), arrive.dot(leave));
  const double defect = 2 * kPi - (exteriorAngle(a, b, c) + exteriorAngle(b, c, a) + turnAtStart);
  errors.defect = std::abs(defect - sphericalExcess(a, b, c));
  errors.gap = (end.point - start.point).norm() / r;
  errors.perimeter = arc(a, b) + arc(b, c) + arc(c, a);
  return errors;
}

}  // namespace

// On the icosphere with longest edge h, faces lie within h^2 / (8 r) of the sphere, so lengths on
// the two differ by a relative O((h / r)^2): a straight walk of length d subtends d / r within
// (h / r)^2 / 2 radians (measured: 0.2 (h / r)^2 at every level), an error that falls fourfold per
// level.
TEST(GeodesicWalk, SubtendsItsLengthOverTheRadiusOnASphere) {
  const SphereErrors coarse = sphereErrors(3), fine = sphereErrors(5);
  for (const SphereErrors& e : {coarse, fine})
    EXPECT_LT(e.subtended, 0.5 * e.edge * e.edge) << e.edge;
  EXPECT_LT(fine.subtended, coarse.subtended / 4);
}

// Discrete Gauss-Bonnet: the heading turns 2 pi minus the angle defects of the vertices the loop
// encloses. Each defect is the curvature of the cell around its vertex, so only cells the loop
// cuts are miscounted: all the curvature within an edge of the loop, perimeter h / r^2 (measured:
// 0.12 h / r or less). The loop misses closing by as little (measured: under 0.02 r).
TEST(GeodesicWalk, TurnsByTheEnclosedAreaOnASphere) {
  const SphereErrors coarse = sphereErrors(3), fine = sphereErrors(5);
  for (const SphereErrors& e : {coarse, fine}) {
    EXPECT_LT(e.defect, e.perimeter * e.edge) << e.edge;
    EXPECT_LT(e.gap, e.perimeter * e.edge) << e.edge;
  }
  EXPECT_LT(fine.defect, coarse.defect / 2);
  EXPECT_LT(fine.gap, coarse.gap / 2);
}
