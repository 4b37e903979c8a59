#include "triangle_intersection.hpp"

#include <algorithm>

#include <Eigen/Geometry>

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

}  // namespace geobrush
