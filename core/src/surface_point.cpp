#include "geobrush/surface_point.hpp"

#include <array>
#include <limits>

namespace geobrush {

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double sum = va + vb + vc;
  // A zero-area triangle that passed every edge test: its corners are as good as any point.
  if (!(sum > 0)) return a;
  return a + (vb / sum) * ab + (vc / sum) * ac;
}

SurfacePoint nearestSurfacePoint(const TriMesh& mesh, const Eigen::Vector3d& query) {
  SurfacePoint best;
  best.distance = std::numeric_limits<double>::infinity();
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> c;
    int i = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto& p = mesh.point(v);
      c[i++] = {p[0], p[1], p[2]};
    }
    const Eigen::Vector3d q = closestPointOnTriangle(query, c[0], c[1], c[2]);
    const double d = (q - query).norm();
    if (d < best.distance) best = {f.idx(), q, d};
  }
  return best;
}

}  // namespace geobrush
