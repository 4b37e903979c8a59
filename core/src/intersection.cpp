#include "geobrush/intersection.hpp"

#include <algorithm>

#include <Eigen/Geometry>
#include <numeric>
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
  std::vector<int> ids(mesh.n_faces());
  std::iota(ids.begin(), ids.end(), 0);
  std::vector<Box> boxes;
  boxes.reserve(ids.size());
  for (int f : ids) {
    Box box;
    for (const auto& p : faceTriangle(mesh, f))
      box.extend(p);
    boxes.push_back(box);
  }
  const Eigen::KdBVH<double, 3, int> tree(ids.begin(), ids.end(), boxes.begin(), boxes.end());
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
      for (auto v : mesh.fv_range(TriMesh::FaceHandle(other)))
        if (std::find(queryCorners.begin(), queryCorners.end(), v.idx()) != queryCorners.end())
          return false;
      count += trianglesIntersect(queryTriangle, faceTriangle(mesh, other), tolerance);
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
