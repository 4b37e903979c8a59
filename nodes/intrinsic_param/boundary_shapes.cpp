// The boundary shapes of the natural and convex-hull modes, and the frame alignment.
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "intrinsic_param.hpp"

#include "geobrush/cut_paste.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

double cross2(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The face's corners in its own plane, counter-clockwise about its normal: (0, 0), (|e1|, 0), ...
std::array<Vector2d, 3> localCorners(const std::array<Vector3d, 3>& x) {
  const Vector3d e1 = x[1] - x[0], e2 = x[2] - x[0];
  const Vector3d a = e1.normalized();
  const Vector3d b = e1.cross(e2).normalized().cross(a);
  return {Vector2d::Zero(), Vector2d(e1.norm(), 0), Vector2d(e2.dot(a), e2.dot(b))};
}

// Andrew's monotone chain: the indices of the points on the hull, without collinear ones.
std::vector<int> convexHullIndices(const std::vector<Vector2d>& points) {
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::tie(points[a].x(), points[a].y(), a) < std::tie(points[b].x(), points[b].y(), b);
  });
  std::vector<int> hull;
  const auto turnsLeft = [&](int o, int a, int b) {
    return cross2(points[a] - points[o], points[b] - points[o]) > 0;
  };
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = hull.size();
    for (int i : order) {
      while (hull.size() >= base + 2 && !turnsLeft(hull[hull.size() - 2], hull.back(), i))
        hull.pop_back();
      hull.push_back(i);
    }
    hull.pop_back();
    std::reverse(order.begin(), order.end());
  }
  return hull;
}

}  // namespace

std::vector<Vector2d> leastSquaresConformalMap(const TriMesh& mesh, int pinA, int pinB,
                                               const std::string& port) {
  const int vertexCount = int(mesh.n_vertices());
  std::vector<Vector2d> pinned(vertexCount, Vector2d::Zero());
  pinned[pinB] = Vector2d(
      (pointOf(mesh, TriMesh::VertexHandle(pinB)) - pointOf(mesh, TriMesh::VertexHandle(pinA)))
          .norm(),
      0);
  std::vector<int> column(vertexCount, -1);
  int unknowns = 0;
  for (int v = 0; v < vertexCount; ++v)
    if (v != pinA && v != pinB) column[v] = 2 * unknowns++;
  // Two rows per face: the real and imaginary parts of sum_k W_k U_k / sqrt(2 area), with
  // W_k = z_{k+2} - z_{k+1} (the local corners as complex numbers) and U_k = u_k + i v_k.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * Eigen::Index(mesh.n_faces()));
  for (auto f : mesh.faces()) {
    std::array<int, 3> c;
    std::array<Vector3d, 3> x;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      c[k] = v.idx();
      x[k++] = pointOf(mesh, v);
    }
    const double doubleArea = (x[1] - x[0]).cross(x[2] - x[0]).norm();
    if (!(doubleArea > 0))
      throw IntrinsicParamError(port, "face " + std::to_string(f.idx()) + " is degenerate");
    const std::array<Vector2d, 3> z = localCorners(x);
    const double weight = 1 / std::sqrt(doubleArea);
    const int re = 2 * f.idx(), im = re + 1;
    for (k = 0; k < 3; ++k) {
      const Vector2d w = weight * (z[(k + 2) % 3] - z[(k + 1) % 3]);
      if (column[c[k]] < 0) {
        const Vector2d& u = pinned[c[k]];
        rhs[re] -= w.x() * u.x() - w.y() * u.y();
        rhs[im] -= w.y() * u.x() + w.x() * u.y();
        continue;
      }
      entries.emplace_back(re, column[c[k]], w.x());
      entries.emplace_back(re, column[c[k]] + 1, -w.y());
      entries.emplace_back(im, column[c[k]], w.y());
      entries.emplace_back(im, column[c[k]] + 1, w.x());
    }
  }
  Eigen::SparseMatrix<double> a(rhs.size(), 2 * unknowns);
  a.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> normal = a.transpose() * a;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  const Eigen::VectorXd x = solver.solve(a.transpose() * rhs);
  if (solver.info() != Eigen::Success || !x.allFinite())
    throw IntrinsicParamError(port, "the free-boundary map (LSCM) is singular");
  std::vector<Vector2d> uv = pinned;
  for (int v = 0; v < vertexCount; ++v)
    if (column[v] >= 0) uv[v] = Vector2d(x[column[v]], x[column[v] + 1]);
  return uv;
}

std::vector<Vector2d> placeOnConvexHull(const std::vector<Vector2d>& loop) {
  const int n = int(loop.size());
  std::vector<char> onHull(n, 0);
  for (int i : convexHullIndices(loop))
    onHull[i] = 1;
  const auto first = std::find(onHull.begin(), onHull.end(), 1);
  if (first == onHull.end()) return loop;
  const int start = int(first - onHull.begin());
  std::vector<Vector2d> placed = loop;
  // Each run between two hull vertices along the loop goes onto the segment joining them.
  for (int a = start, steps = 0; steps < n;) {
    std::vector<double> along{0.0};
    int b = a;
    do {
      const int next = (b + 1) % n;
      along.push_back(along.back() + (loop[next] - loop[b]).norm());
      b = next;
      ++steps;
    } while (!onHull[b]);
    for (std::size_t s = 1; s + 1 < along.size(); ++s) {
      const double t = along.back() > 0 ? along[s] / along.back() : 0.0;
      placed[(a + int(s)) % n] = (1 - t) * loop[a] + t * loop[b];
    }
    a = b;
  }
  return placed;
}

Eigen::Matrix3d frameAlignment(const Canvas& feature, const std::vector<Vector2d>& featureUv,
                               const Parameterization& frame) {
  if (!frame.canvas || frame.uv.size() != frame.canvas->surface.n_vertices() ||
      frame.canvas->sourceVertex.size() != frame.uv.size())
    throw IntrinsicParamError("frame", "the frame's uv does not match its canvas");
  const MeshPtr& mine = feature.source;
  const MeshPtr& theirs = frame.canvas->source;
  if (!mine || !theirs || feature.sourceVertex.size() != feature.surface.n_vertices() ||
      (mine != theirs && mine->contentHash() != theirs->contentHash()))
    throw IntrinsicParamError("frame", "the frame's canvas does not lie on F's source mesh");
  std::vector<std::pair<int, int>> bySource;  // (source vertex, frame canvas vertex)
  for (std::size_t v = 0; v < frame.uv.size(); ++v)
    bySource.emplace_back(frame.canvas->sourceVertex[v], int(v));
  std::sort(bySource.begin(), bySource.end());
  std::vector<std::pair<Vector2d, Vector2d>> matches;
  for (int v : feature.boundary) {
    const auto at =
        std::lower_bound(bySource.begin(), bySource.end(), std::pair(feature.sourceVertex[v], -1));
    if (at != bySource.end() && at->first == feature.sourceVertex[v])
      matches.emplace_back(featureUv[v], frame.uv[at->second]);
  }
  std::vector<Vector2d> from, to;
  for (const auto& [mine, theirs] : matches) {
    from.push_back(mine);
    to.push_back(theirs);
  }
  const auto spreads = [](const std::vector<Vector2d>& points) {
    return std::any_of(points.begin(), points.end(),
                       [&](const Vector2d& p) { return p != points.front(); });
  };
  const bool spread = matches.size() >= 3 && spreads(from) && spreads(to);
  if (!spread)
    throw IntrinsicParamError("frame", "only " + std::to_string(matches.size()) +
                                           " of F's boundary vertices have distinct uv on the "
                                           "frame's canvas; 3 are needed");
  return fitSimilarity2d(from, to);
}

}  // namespace geobrush
