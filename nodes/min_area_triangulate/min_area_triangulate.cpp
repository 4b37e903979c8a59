#include "min_area_triangulate.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "geobrush/intersection.hpp"

namespace geobrush {
namespace {

// The loop's coordinates, one array each, so that the programme's inner loop streams over k.
struct LoopCoordinates {
  std::vector<double> x, y, z;
  explicit LoopCoordinates(const std::vector<Eigen::Vector3d>& loop) {
    for (const auto& p : loop) {
      x.push_back(p.x());
      y.push_back(p.y());
      z.push_back(p.z());
    }
  }
};

// Half the norm of (a x b): the area of the triangle with sides a and b from one corner.
inline double halfCrossNorm(double ax, double ay, double az, double bx, double by, double bz) {
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
}

// The DP of Sec. 5.1 over a table T with T(i, i + 1) = base(i, i + 1) and
// T(i, j) = min_k T(i, k) + T(k, j) + term(i, k, j), plus add(i, j). For the area, T = W, term =
// the area, add = 0. For the perimeter the chords' lengths d are folded into T = W + d(i, j):
// W(i, k) + W(k, j) + d(i, k) + d(k, j) + d(i, j) = T(i, k) + T(k, j) + d(i, j), so term = 0 and
// add = 2 d(i, j), and the inner loop needs no root. T(i, j), i < j, sits at [i n + j] and again
// at [j n + i], so that both T(i, k) and T(k, j) run contiguously over k.
struct DpTables {
  int n = 0;
  std::vector<double> t;
  std::vector<std::int32_t> split;
  double at(int i, int j) const { return t[std::size_t(i) * n + j]; }
  void set(int i, int j, double value) {
    t[std::size_t(i) * n + j] = t[std::size_t(j) * n + i] = value;
  }
};

double chord(const LoopCoordinates& c, int i, int j) {
  const double dx = c.x[i] - c.x[j], dy = c.y[i] - c.y[j], dz = c.z[i] - c.z[j];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Triangles with 4 sqrt(3) area / (sum of squared sides) below this are degenerate: corners on
// one line (a loop running straight along mesh edges) span no area and would fold onto the faces
// beside them.
constexpr double kDegenerateQuality = 1e-9;

// A cost no triangulation without degenerate triangles reaches: n triangles of the loop's
// diameter squared.
double degeneratePenalty(const LoopCoordinates& c) {
  double diameter2 = 0;
  for (std::size_t i = 0; i < c.x.size(); ++i)
    for (std::size_t j = i + 1; j < c.x.size(); ++j) {
      const double dx = c.x[i] - c.x[j], dy = c.y[i] - c.y[j], dz = c.z[i] - c.z[j];
      diameter2 = std::max(diameter2, dx * dx + dy * dy + dz * dz);
    }
  return double(c.x.size()) * std::max(diameter2, 1.0);
}

// The penalty where the triangle with sides a and b from one corner is degenerate, else 0.
inline double degenerate(double ax, double ay, double az, double bx, double by, double bz,
                         double area, double penalty) {
  const double cx = bx - ax, cy = by - ay, cz = bz - az;
  const double sides =
      ax * ax + ay * ay + az * az + bx * bx + by * by + bz * bz + cx * cx + cy * cy + cz * cz;
  return 4 * std::sqrt(3.0) * area <= kDegenerateQuality * sides ? penalty : 0.0;
}

// Row by row from i = n - 3 down, each row from j = i + 2 up: T(i, k) and T(k, j) are ready.
// Degenerate triangles cost a penalty, so that they are used only where nothing else spans the
// loop.
DpTables solveTables(const std::vector<Eigen::Vector3d>& loop, TriangulationObjective objective) {
  const bool area = objective == TriangulationObjective::Area;
  const LoopCoordinates c(loop);
  const double penalty = degeneratePenalty(c);
  DpTables t;
  t.n = int(loop.size());
  const std::size_t cells = std::size_t(t.n) * std::size_t(t.n);
  t.t.assign(cells, 0.0);
  t.split.assign(cells, -1);
  for (int i = 0; i + 1 < t.n; ++i)
    t.set(i, i + 1, area ? 0.0 : chord(c, i, i + 1));
  std::vector<double> candidate(std::size_t(t.n));
  for (int i = t.n - 3; i >= 0; --i) {
    const double* tik = &t.t[std::size_t(i) * t.n];
    for (int j = i + 2; j < t.n; ++j) {
      const double* tkj = &t.t[std::size_t(j) * t.n];
      const double bx = c.x[j] - c.x[i], by = c.y[j] - c.y[i], bz = c.z[j] - c.z[i];
      for (int k = i + 1; k < j; ++k) {
        const double ax = c.x[k] - c.x[i], ay = c.y[k] - c.y[i], az = c.z[k] - c.z[i];
        const double triangle = halfCrossNorm(ax, ay, az, bx, by, bz);
        candidate[k] = tik[k] + tkj[k] + (area ? triangle : 0.0) +
                       degenerate(ax, ay, az, bx, by, bz, triangle, penalty);
      }
      int best = i + 1;
      for (int k = i + 2; k < j; ++k)
        if (candidate[k] < candidate[best]) best = k;  // strict: ties keep the smallest k
      t.set(i, j, candidate[best] + (area ? 0.0 : 2.0 * chord(c, i, j)));
      t.split[std::size_t(i) * t.n + j] = best;
    }
  }
  return t;
}

// The triangles of the optimal splits, from (0, n - 1) down, each polygon before its right part.
std::vector<std::array<int, 3>> collectTriangles(const DpTables& t) {
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(std::size_t(t.n - 2));
  std::vector<std::pair<int, int>> pending{{0, t.n - 1}};
  while (!pending.empty()) {
    const auto [i, j] = pending.back();
    pending.pop_back();
    if (j - i < 2) continue;
    const int k = t.split[std::size_t(i) * t.n + j];
    triangles.push_back({i, j, k});
    pending.emplace_back(k, j);
    pending.emplace_back(i, k);
  }
  return triangles;
}

// Throws unless `canvas.boundary` is a loop of distinct surface vertices along boundary halfedges
// with a length the programme accepts.
void checkLoop(const Canvas& canvas, const MinAreaOptions& options) {
  const auto& loop = canvas.boundary;
  const TriMesh& surface = canvas.surface;
  if (loop.size() < 3)
    throw std::invalid_argument("its boundary loop has " + std::to_string(loop.size()) +
                                " vertices; a base needs at least 3");
  if (loop.size() > std::size_t(options.maxLoopVertices))
    throw std::invalid_argument("its boundary loop has " + std::to_string(loop.size()) +
                                " vertices; the triangulation takes at most " +
                                std::to_string(options.maxLoopVertices) + " (O(n^2) memory)");
  std::vector<char> seen(surface.n_vertices(), 0);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int v = loop[i];
    if (v < 0 || std::size_t(v) >= surface.n_vertices())
      throw std::invalid_argument("its boundary names vertex " + std::to_string(v) +
                                  ", which its surface lacks");
    if (seen[std::size_t(v)])
      throw std::invalid_argument("its boundary repeats vertex " + std::to_string(v));
    seen[std::size_t(v)] = 1;
  }
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int from = loop[i], to = loop[(i + 1) % loop.size()];
    const auto h = surface.find_halfedge(TriMesh::VertexHandle(from), TriMesh::VertexHandle(to));
    if (!h.is_valid() || !surface.is_boundary(h))
      throw std::invalid_argument(
          "its boundary does not run along the surface's boundary "
          "halfedges (from vertex " +
          std::to_string(from) + " to " + std::to_string(to) + ")");
  }
}

}  // namespace

double triangleCost(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    TriangulationObjective objective) {
  if (objective == TriangulationObjective::Area) {
    const Eigen::Vector3d u = b - a, w = c - a;
    return halfCrossNorm(u.x(), u.y(), u.z(), w.x(), w.y(), w.z());
  }
  return (b - a).norm() + (c - b).norm() + (a - c).norm();
}

LoopTriangulation optimalTriangulation(const std::vector<Eigen::Vector3d>& loop,
                                       TriangulationObjective objective) {
  if (loop.size() < 3) throw std::invalid_argument("a polygon needs at least 3 vertices");
  const DpTables tables = solveTables(loop, objective);
  LoopTriangulation result;
  result.triangles = collectTriangles(tables);
  // Summed again rather than read from the table, which holds the degenerate triangles' penalty.
  for (const auto& [i, j, k] : result.triangles) {
    result.cost += triangleCost(loop[i], loop[k], loop[j], objective);
    const Eigen::Vector3d a = loop[k] - loop[i], b = loop[j] - loop[i];
    result.degenerate +=
        degenerate(a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), 0.5 * a.cross(b).norm(), 1.0) > 0;
  }
  return result;
}

TriMesh triangulationMesh(const std::vector<Eigen::Vector3d>& loop, const LoopTriangulation& t) {
  TriMesh mesh;
  for (const auto& p : loop)
    mesh.add_vertex(toPoint(p));
  for (const auto& tri : t.triangles)
    mesh.add_face(TriMesh::VertexHandle(tri[0]), TriMesh::VertexHandle(tri[1]),
                  TriMesh::VertexHandle(tri[2]));
  return mesh;
}

// Sec. 5.1: B0 spans F's boundary loop with the triangulation of least total area (Eq. 1).
MinAreaResult minAreaTriangulate(const Canvas& canvas, const MinAreaOptions& options) {
  checkLoop(canvas, options);
  std::vector<Eigen::Vector3d> loop;
  loop.reserve(canvas.boundary.size());
  for (int v : canvas.boundary)
    loop.push_back(pointOf(canvas.surface, v));
  const LoopTriangulation triangulation = optimalTriangulation(loop, options.objective);

  MinAreaResult result;
  result.base = triangulationMesh(loop, triangulation);
  result.objective = triangulation.cost;
  result.degenerate = triangulation.degenerate;
  for (const auto& tri : triangulation.triangles) {
    result.area +=
        triangleCost(loop[tri[0]], loop[tri[1]], loop[tri[2]], TriangulationObjective::Area);
    // Each interior edge is the side (i, k) or (k, j) of exactly one triangle (the side (i, j)
    // of another); such sides with a gap of 1 lie on the loop.
    const int i = tri[0], j = tri[1], k = tri[2];
    if (k - i > 1) result.interiorEdgeLength += (loop[k] - loop[i]).norm();
    if (j - k > 1) result.interiorEdgeLength += (loop[j] - loop[k]).norm();
  }
  std::vector<int> faces(result.base.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  result.selfIntersections =
      selfIntersections(result.base, faces, 1e-12 * boundingDiagonal(result.base));
  return result;
}

}  // namespace geobrush
