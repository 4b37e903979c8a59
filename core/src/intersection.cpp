#include "geobrush/intersection.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <unsupported/Eigen/BVH>

namespace geobrush {
namespace {

// Whether the projections of a and b on `axis` are more than `tolerance` apart.
bool separates(const Eigen::Vector3d& axis, const Triangle3& a, const Triangle3& b,
               double tolerance) {
  const double length = axis.norm();
  if (length == 0) return false;
  const Eigen::Vector3d n = axis / length;
  const double a0 = n.dot(a[0]), a1 = n.dot(a[1]), a2 = n.dot(a[2]);
  const double b0 = n.dot(b[0]), b1 = n.dot(b[1]), b2 = n.dot(b[2]);
  const double aMin = std::min({a0, a1, a2}), aMax = std::max({a0, a1, a2});
  const double bMin = std::min({b0, b1, b2}), bMax = std::max({b0, b1, b2});
  return aMax + tolerance < bMin || bMax + tolerance < aMin;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Whether two segments of a plane cross at a point inside both (ends inside are caught by the
// inside tests of the caller).
bool segmentsCross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d) {
  const double o1 = cross2(b - a, c - a), o2 = cross2(b - a, d - a);
  const double o3 = cross2(d - c, a - c), o4 = cross2(d - c, b - c);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

// Barycentric inside test in the triangle's plane, with `tolerance` as a length.
bool insideTriangle(const Eigen::Vector3d& p, const Triangle3& t, const Eigen::Vector3d& unitNormal,
                    double tolerance) {
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d edge = t[(k + 1) % 3] - t[k];
    const Eigen::Vector3d inward = unitNormal.cross(edge).normalized();
    if (inward.dot(p - t[k]) < -tolerance) return false;
  }
  return true;
}

// Whether the segment from a to b meets the triangle.
bool segmentMeetsTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Triangle3& t,
                          double tolerance) {
  const Eigen::Vector3d normal = (t[1] - t[0]).cross(t[2] - t[0]);
  if (normal.norm() == 0.0) return false;
  const Eigen::Vector3d n = normal.normalized();
  const double da = n.dot(a - t[0]), db = n.dot(b - t[0]);
  if ((da > tolerance && db > tolerance) || (da < -tolerance && db < -tolerance)) return false;
  if (std::abs(da) <= tolerance && std::abs(db) <= tolerance) {
    // In the plane: an end inside, or the segment crossing an edge.
    if (insideTriangle(a, t, n, tolerance) || insideTriangle(b, t, n, tolerance)) return true;
    const Eigen::Vector3d u = (t[1] - t[0]).normalized(), v = n.cross(u);
    const auto flat = [&](const Eigen::Vector3d& p) {
      return Eigen::Vector2d(u.dot(p - t[0]), v.dot(p - t[0]));
    };
    for (int k = 0; k < 3; ++k)
      if (segmentsCross(flat(a), flat(b), flat(t[k]), flat(t[(k + 1) % 3]))) return true;
    return false;
  }
  const Eigen::Vector3d crossing = std::abs(da) <= tolerance   ? a
                                   : std::abs(db) <= tolerance ? b
                                                               : a + (b - a) * (da / (da - db));
  return insideTriangle(crossing, t, n, tolerance);
}

// Faces sharing corners meet beyond them when an edge of one, away from the shared vertex,
// meets the other (one shared vertex), or when they fold flat onto each other (a shared edge).
bool adjacentTrianglesMeet(const Triangle3& a, const Triangle3& b, const std::array<int, 3>& ca,
                           const std::array<int, 3>& cb, double tolerance) {
  std::array<int, 3> sharedInA{}, sharedInB{};
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (ca[i] == cb[j]) {
        sharedInA[std::size_t(shared)] = i;
        sharedInB[std::size_t(shared++)] = j;
      }
  if (shared == 1) {
    const int i = sharedInA[0], j = sharedInB[0];
    return segmentMeetsTriangle(b[(j + 1) % 3], b[(j + 2) % 3], a, tolerance) ||
           segmentMeetsTriangle(a[(i + 1) % 3], a[(i + 2) % 3], b, tolerance);
  }
  if (shared != 2) return false;
  const int thirdA = 3 - sharedInA[0] - sharedInA[1], thirdB = 3 - sharedInB[0] - sharedInB[1];
  const Eigen::Vector3d e0 = a[sharedInA[0]], along = (a[sharedInA[1]] - e0).normalized();
  const Eigen::Vector3d normal = (a[1] - a[0]).cross(a[2] - a[0]);
  if (normal.norm() == 0.0 || std::abs(normal.normalized().dot(b[thirdB] - e0)) > tolerance)
    return false;
  const Eigen::Vector3d pa = a[thirdA] - e0, pb = b[thirdB] - e0;
  return (pa - along * along.dot(pa)).dot(pb - along * along.dot(pb)) > 0.0;
}

double twiceArea(const std::vector<Eigen::Vector2d>& polygon) {
  double sum = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    sum += cross2(polygon[i], polygon[(i + 1) % polygon.size()]);
  return sum;
}

// The part of a convex polygon on the left of the line from a to b (Sutherland-Hodgman).
std::vector<Eigen::Vector2d> keepLeftOf(const std::vector<Eigen::Vector2d>& polygon,
                                        const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  std::vector<Eigen::Vector2d> kept;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& p = polygon[i];
    const Eigen::Vector2d& q = polygon[(i + 1) % polygon.size()];
    const double sp = cross2(b - a, p - a), sq = cross2(b - a, q - a);
    if (sp >= 0) kept.push_back(p);
    if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) kept.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return kept;
}

}  // namespace

bool trianglesIntersect(const Triangle3& a, const Triangle3& b, double tolerance) {
  const std::array<Eigen::Vector3d, 3> ea{a[1] - a[0], a[2] - a[1], a[0] - a[2]};
  const std::array<Eigen::Vector3d, 3> eb{b[1] - b[0], b[2] - b[1], b[0] - b[2]};
  const Eigen::Vector3d na = ea[0].cross(ea[1]), nb = eb[0].cross(eb[1]);
  if (na.norm() == 0 || nb.norm() == 0) return false;
  if (separates(na, a, b, tolerance) || separates(nb, a, b, tolerance)) return false;
  for (const auto& u : ea)
    for (const auto& v : eb)
      if (separates(u.cross(v), a, b, tolerance)) return false;
  // Coplanar (or nearly) triangles are parted, if at all, along a normal of an edge in the plane.
  for (const auto& u : ea)
    if (separates(na.cross(u), a, b, tolerance)) return false;
  for (const auto& v : eb)
    if (separates(nb.cross(v), a, b, tolerance)) return false;
  return true;
}

bool trianglesOverlapAlong(const Eigen::Vector3d& direction, const Triangle3& a, const Triangle3& b,
                           double share) {
  if (direction.norm() == 0) return false;
  const Eigen::Vector3d u = direction.unitOrthogonal(), v = direction.normalized().cross(u);
  const auto project = [&](const Triangle3& t) {
    std::vector<Eigen::Vector2d> p;
    for (const Eigen::Vector3d& x : t)
      p.emplace_back(u.dot(x), v.dot(x));
    if (twiceArea(p) < 0) std::swap(p[1], p[2]);
    return p;
  };
  const std::vector<Eigen::Vector2d> pa = project(a), pb = project(b);
  const double smaller = std::min(twiceArea(pa), twiceArea(pb));
  if (smaller <= 0) return false;
  std::vector<Eigen::Vector2d> common = pa;
  for (std::size_t i = 0; i < 3 && common.size() >= 3; ++i)
    common = keepLeftOf(common, pb[i], pb[(i + 1) % 3]);
  return common.size() >= 3 && twiceArea(common) > share * smaller;
}

Triangle3 faceTriangle(const TriMesh& mesh, int f) {
  Triangle3 t;
  int k = 0;
  for (auto v : mesh.fv_range(TriMesh::FaceHandle(f))) {
    const auto& p = mesh.point(v);
    t[std::size_t(k++)] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  return t;
}

std::size_t selfIntersections(const TriMesh& mesh, const std::vector<int>& faces,
                              double tolerance) {
  using Box = Eigen::AlignedBox3d;
  std::vector<Box> boxes(mesh.n_faces());
  for (std::size_t f = 0; f < boxes.size(); ++f)
    for (const auto& p : faceTriangle(mesh, int(f)))
      boxes[f].extend(p);
  // Only faces near the listed ones can meet them: the tree holds those alone.
  Box near;
  for (int f : faces)
    near.extend(boxes[std::size_t(f)]);
  near = Box(near.min().array() - tolerance, near.max().array() + tolerance);
  std::vector<int> ids;
  std::vector<Box> idBoxes;
  for (std::size_t f = 0; f < boxes.size(); ++f)
    if (boxes[f].intersects(near)) {
      ids.push_back(int(f));
      idBoxes.push_back(boxes[f]);
    }
  const Eigen::KdBVH<double, 3, int> tree(ids.begin(), ids.end(), idBoxes.begin(), idBoxes.end());
  std::vector<char> listed(mesh.n_faces(), 0);
  for (int f : faces)
    listed[std::size_t(f)] = 1;

  // Eigen's BVH visitor: descends into volumes that meet the query box, tests the faces there.
  struct Intersector {
    const TriMesh& mesh;
    const std::vector<Box>& boxes;
    const std::vector<char>& listed;
    double tolerance;
    int query = 0;
    Triangle3 queryTriangle{};
    std::array<int, 3> queryCorners{};
    std::size_t count = 0;
    bool intersectVolume(const Box& volume) const {
      return volume.intersects(boxes[std::size_t(query)]);
    }
    bool intersectObject(int other) {
      // Each pair once: from its smaller listed face.
      if (other == query || (listed[std::size_t(other)] && other < query)) return false;
      if (!boxes[std::size_t(other)].intersects(boxes[std::size_t(query)])) return false;
      std::array<int, 3> corners{};
      bool shares = false;
      int k = 0;
      for (auto v : mesh.fv_range(TriMesh::FaceHandle(other))) {
        corners[std::size_t(k++)] = v.idx();
        shares |=
            std::find(queryCorners.begin(), queryCorners.end(), v.idx()) != queryCorners.end();
      }
      const Triangle3 triangle = faceTriangle(mesh, other);
      count +=
          shares ? adjacentTrianglesMeet(queryTriangle, triangle, queryCorners, corners, tolerance)
                 : trianglesIntersect(queryTriangle, triangle, tolerance);
      return false;
    }
  };
  Intersector intersector{mesh, boxes, listed, tolerance, 0, {}, {}, 0};
  for (int f : faces) {
    intersector.query = f;
    intersector.queryTriangle = faceTriangle(mesh, f);
    int k = 0;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      intersector.queryCorners[std::size_t(k++)] = v.idx();
    Eigen::BVIntersect(tree, intersector);
  }
  return intersector.count;
}

}  // namespace geobrush
