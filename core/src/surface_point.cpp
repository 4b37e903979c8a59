#include "geobrush/surface_point.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

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

namespace {

std::array<Eigen::Vector3d, 3> corners(const TriMesh& mesh, TriMesh::FaceHandle f) {
  std::array<Eigen::Vector3d, 3> c;
  int i = 0;
  for (auto v : mesh.fv_range(f)) {
    const auto& p = mesh.point(v);
    c[std::size_t(i++)] = {p[0], p[1], p[2]};
  }
  return c;
}

std::vector<Eigen::AlignedBox3d> faceBoxes(const std::vector<std::array<Eigen::Vector3d, 3>>& t) {
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(t.size());
  for (const auto& [a, b, c] : t)
    boxes.emplace_back(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
  return boxes;
}

std::vector<int> faceIndices(std::size_t count) {
  std::vector<int> faces(count);
  std::iota(faces.begin(), faces.end(), 0);
  return faces;
}

// Keeps the nearest face with nearestSurfacePoint's tie rule (lowest index). The tree skips
// volumes whose bound is not below the best distance so far; bounds lowered by one part in 1e12
// (and below 0 for a volume touching the query) keep the volumes that may hold a tie.
class NearestFace {
 public:
  using Scalar = double;
  NearestFace(const std::vector<std::array<Eigen::Vector3d, 3>>& triangles,
              const Eigen::Vector3d& query)
      : triangles_(triangles), query_(query) {
    best_.distance = std::numeric_limits<double>::infinity();
  }
  double minimumOnVolume(const Eigen::AlignedBox3d& box) const {
    return std::sqrt(box.squaredExteriorDistance(query_)) * (1 - 1e-12) -
           std::numeric_limits<double>::denorm_min();
  }
  double minimumOnObject(int face) {
    const auto& [a, b, c] = triangles_[std::size_t(face)];
    const Eigen::Vector3d q = closestPointOnTriangle(query_, a, b, c);
    const double d = (q - query_).norm();
    if (d < best_.distance || (d == best_.distance && face < best_.face)) best_ = {face, q, d};
    return d;
  }
  const SurfacePoint& best() const { return best_; }

 private:
  const std::vector<std::array<Eigen::Vector3d, 3>>& triangles_;
  Eigen::Vector3d query_;
  SurfacePoint best_;
};

}  // namespace

SurfaceLocator::SurfaceLocator(const TriMesh& mesh) {
  if (mesh.n_faces() == 0) throw std::invalid_argument("a surface locator needs a face");
  triangles_.reserve(mesh.n_faces());
  for (auto f : mesh.faces())
    triangles_.push_back(corners(mesh, f));
  const std::vector<int> faces = faceIndices(triangles_.size());
  const auto boxes = faceBoxes(triangles_);
  tree_.init(faces.begin(), faces.end(), boxes.begin(), boxes.end());
}

SurfacePoint SurfaceLocator::nearest(const Eigen::Vector3d& query) const {
  NearestFace search(triangles_, query);
  Eigen::BVMinimize(tree_, search);
  return search.best();
}

}  // namespace geobrush
