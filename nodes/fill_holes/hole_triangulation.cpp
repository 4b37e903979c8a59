// A graded triangulation of a simple polygon: ear clipping, Lawson flips to the constrained
// Delaunay triangulation, then Liepa's centroid splits with flips after each pass (Liepa,
// "Filling holes in meshes", SGP 2003, Sec. 3.2), all in the plane.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <stdexcept>
#include <unordered_map>

#include "fill_holes.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;

double orient(const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// > 0 when d lies inside the circle through the counter-clockwise a, b, c.
double inCircle(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d) {
  const Vector2d ad = a - d, bd = b - d, cd = c - d;
  return ad.squaredNorm() * orient(Vector2d::Zero(), bd, cd) -
         bd.squaredNorm() * orient(Vector2d::Zero(), ad, cd) +
         cd.squaredNorm() * orient(Vector2d::Zero(), ad, bd);
}

bool onClosedTriangle(const Vector2d& p, const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

std::vector<std::array<int, 3>> clipEars(const std::vector<Vector2d>& polygon) {
  std::vector<int> left(polygon.size());
  for (std::size_t i = 0; i < left.size(); ++i)
    left[i] = int(i);
  std::vector<std::array<int, 3>> triangles;
  std::size_t i = 0, misses = 0;
  while (left.size() > 3) {
    if (misses > left.size()) throw std::runtime_error("the polygon has no ear: it is not simple");
    const std::size_t n = left.size();
    const int a = left[(i + n - 1) % n], b = left[i % n], c = left[(i + 1) % n];
    bool ear = orient(polygon[a], polygon[b], polygon[c]) > 0;
    for (std::size_t k = 0; ear && k < n; ++k) {
      const int p = left[k];
      if (p == a || p == b || p == c) continue;
      // Any other point on the ear's closed triangle blocks it (a collinear one on its diagonal
      // too).
      if (onClosedTriangle(polygon[p], polygon[a], polygon[b], polygon[c])) ear = false;
    }
    if (!ear) {
      i = (i + 1) % n;
      ++misses;
      continue;
    }
    triangles.push_back({a, b, c});
    left.erase(left.begin() + std::ptrdiff_t(i % n));
    i = (i % left.size());
    misses = 0;
  }
  triangles.push_back({left[0], left[1], left[2]});
  return triangles;
}

std::uint64_t edgeKey(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

// Triangles with a map from each directed edge to its triangle, flipped toward Delaunay.
class Triangulation {
 public:
  Triangulation(std::vector<Vector2d> points, std::vector<std::array<int, 3>> triangles)
      : points_(std::move(points)), triangles_(std::move(triangles)) {
    for (int t = 0; t < int(triangles_.size()); ++t)
      link(t);
    for (int t = 0; t < int(triangles_.size()); ++t)
      queueEdges(t);
  }

  PlanarPatch release() { return {std::move(points_), std::move(triangles_)}; }
  std::vector<Vector2d>& points() { return points_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

  // Lawson's flips over the queued edges; a cap guards against rounding cycles.
  void flipToDelaunay() {
    std::size_t budget = 64 * (triangles_.size() + 16);
    while (!queue_.empty() && budget-- > 0) {
      const auto [a, b] = queue_.front();
      queue_.pop_front();
      flipIfNotDelaunay(a, b);
    }
    queue_.clear();
  }

  int split(int t, const Vector2d& at) {
    const int v = int(points_.size());
    points_.push_back(at);
    const auto [a, b, c] = triangles_[std::size_t(t)];
    triangles_[std::size_t(t)] = {a, b, v};
    triangles_.push_back({b, c, v});
    triangles_.push_back({c, a, v});
    link(t);
    link(int(triangles_.size()) - 2);
    link(int(triangles_.size()) - 1);
    queue_.push_back({a, b});
    queue_.push_back({b, c});
    queue_.push_back({c, a});
    return v;
  }

 private:
  void link(int t) {
    const auto& tri = triangles_[std::size_t(t)];
    for (int k = 0; k < 3; ++k)
      edges_[edgeKey(tri[k], tri[(k + 1) % 3])] = t;
  }
  void queueEdges(int t) {
    const auto& tri = triangles_[std::size_t(t)];
    for (int k = 0; k < 3; ++k)
      queue_.push_back({tri[k], tri[(k + 1) % 3]});
  }
  int third(int t, int a, int b) const {
    for (int v : triangles_[std::size_t(t)])
      if (v != a && v != b) return v;
    return -1;
  }

  void flipIfNotDelaunay(int a, int b) {
    const auto left = edges_.find(edgeKey(a, b)), right = edges_.find(edgeKey(b, a));
    if (left == edges_.end() || right == edges_.end()) return;  // a border edge
    const int t1 = left->second, t2 = right->second;
    const int c = third(t1, a, b), d = third(t2, a, b);
    const Vector2d &pa = points_[a], &pb = points_[b], &pc = points_[c], &pd = points_[d];
    const double scale = (pa - pb).squaredNorm() + (pc - pd).squaredNorm();
    if (inCircle(pa, pb, pc, pd) <= 1e-12 * scale * scale) return;
    if (orient(pa, pd, pc) <= 0 || orient(pd, pb, pc) <= 0) return;  // not convex
    edges_.erase(left);
    edges_.erase(edges_.find(edgeKey(b, a)));
    triangles_[std::size_t(t1)] = {a, d, c};
    triangles_[std::size_t(t2)] = {d, b, c};
    link(t1);
    link(t2);
    queue_.push_back({a, d});
    queue_.push_back({d, b});
    queue_.push_back({b, c});
    queue_.push_back({c, a});
  }

  std::vector<Vector2d> points_;
  std::vector<std::array<int, 3>> triangles_;
  std::unordered_map<std::uint64_t, int> edges_;
  std::deque<std::pair<int, int>> queue_;
};

// Liepa's test: the centroid is farther from each corner than both its size and the corner's.
bool tooLarge(const std::array<int, 3>& tri, const std::vector<Vector2d>& points,
              const std::vector<double>& size, double density, Vector2d& centroid,
              double& centroidSize) {
  centroid = (points[tri[0]] + points[tri[1]] + points[tri[2]]) / 3.0;
  centroidSize = (size[tri[0]] + size[tri[1]] + size[tri[2]]) / 3.0;
  for (int v : tri) {
    const double d = density * (centroid - points[v]).norm();
    if (d <= centroidSize || d <= size[v]) return false;
  }
  return true;
}

}  // namespace

bool isSimplePolygon(const std::vector<Vector2d>& polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return false;
  auto segmentsTouch = [](const Vector2d& a, const Vector2d& b, const Vector2d& c,
                          const Vector2d& d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
                 o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
      return true;
    auto onSegment = [](const Vector2d& p, const Vector2d& q, const Vector2d& r) {
      return orient(p, q, r) == 0 && r.x() >= std::min(p.x(), q.x()) &&
             r.x() <= std::max(p.x(), q.x()) && r.y() >= std::min(p.y(), q.y()) &&
             r.y() <= std::max(p.y(), q.y());
    };
    return onSegment(a, b, c) || onSegment(a, b, d) || onSegment(c, d, a) || onSegment(c, d, b);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Vector2d &a = polygon[i], &b = polygon[(i + 1) % n];
    if (a == b) return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segmentsTouch(a, b, polygon[j], polygon[(j + 1) % n])) return false;
    }
  }
  return true;
}

PlanarPatch triangulatePolygon(const std::vector<Vector2d>& border,
                               const std::vector<double>& borderSize, double density) {
  if (border.size() < 3) throw std::runtime_error("a polygon needs 3 points");
  Triangulation mesh(border, clipEars(border));
  mesh.flipToDelaunay();
  std::vector<double> size = borderSize;
  // Each pass at least splits one triangle whose size is above the smallest border size, so the
  // cap is never reached on a polygon whose sizes are its own edge lengths.
  for (int pass = 0; pass < 64; ++pass) {
    bool split = false;
    const int count = int(mesh.triangles().size());
    for (int t = 0; t < count; ++t) {
      Vector2d centroid;
      double centroidSize = 0.0;
      if (!tooLarge(mesh.triangles()[std::size_t(t)], mesh.points(), size, density, centroid,
                    centroidSize))
        continue;
      mesh.split(t, centroid);
      size.push_back(centroidSize);
      split = true;
    }
    mesh.flipToDelaunay();
    if (!split) break;
  }
  return mesh.release();
}

}  // namespace geobrush
