#include "point_insert.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

namespace geobrush {
namespace {

using CellKey = std::array<std::int64_t, 3>;

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::int64_t c : k)
      h = (h ^ std::uint64_t(c)) * 0x100000001b3ull;
    return std::size_t(h);
  }
};

// The vertices binned in cubes of side `cell`: which of them lie near a point.
class SpacingGrid {
 public:
  explicit SpacingGrid(double cell) : cell_(cell) {}

  void add(const Eigen::Vector3d& p, int vertex) { cells_[keyOf(p)].push_back({p, vertex}); }

  // The least distance from p to a binned vertex other than `except` among those within
  // `reach` cells of p's cell; +inf where there is none.
  double nearest(const Eigen::Vector3d& p, int reach, int except = -1) const {
    const CellKey at = keyOf(p);
    double best = std::numeric_limits<double>::infinity();
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) {
          const auto it = cells_.find({at[0] + dx, at[1] + dy, at[2] + dz});
          if (it == cells_.end()) continue;
          for (const Binned& b : it->second)
            if (b.vertex != except) best = std::min(best, (b.point - p).norm());
        }
    return best;
  }

 private:
  struct Binned {
    Eigen::Vector3d point;
    int vertex;
  };
  CellKey keyOf(const Eigen::Vector3d& p) const {
    return {std::int64_t(std::floor(p.x() / cell_)), std::int64_t(std::floor(p.y() / cell_)),
            std::int64_t(std::floor(p.z() / cell_))};
  }
  double cell_;
  std::unordered_map<CellKey, std::vector<Binned>, CellKeyHash> cells_;
};

double edgeLength(const TriMesh& mesh, TriMesh::EdgeHandle e) {
  return mesh.calc_edge_length(e);
}

// The edges longer than `longest` that may be split, longest first (ties by index).
std::vector<TriMesh::EdgeHandle> splitCandidates(const TriMesh& mesh, double longest,
                                                 const std::vector<char>& declined,
                                                 bool splitBoundary) {
  std::vector<std::pair<double, int>> found;
  for (const auto e : mesh.edges()) {
    if (declined[std::size_t(e.idx())] || (!splitBoundary && mesh.is_boundary(e))) continue;
    const double length = edgeLength(mesh, e);
    if (length > longest) found.emplace_back(-length, e.idx());
  }
  std::sort(found.begin(), found.end());
  std::vector<TriMesh::EdgeHandle> edges;
  for (const auto& [negative, e] : found)
    edges.emplace_back(e);
  return edges;
}

void requireRepresentable(const TriMesh& mesh, double cell) {
  for (const auto v : mesh.vertices())
    for (int d = 0; d < 3; ++d) {
      const double c = mesh.point(v)[d] / cell;
      if (!std::isfinite(c) || std::abs(c) > 1e15)
        throw PointInsertError("delta_min is too small for the template's coordinates");
    }
}

double closestInsertedDistance(const TriMesh& mesh, std::size_t firstInserted,
                               const SpacingGrid& grid) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t v = firstInserted; v < mesh.n_vertices(); ++v)
    closest = std::min(closest,
                       grid.nearest(toEigen(mesh.point(TriMesh::VertexHandle(int(v)))), 2, int(v)));
  return closest;
}

// Refused before any work where the template's area alone needs more than the limit: once every
// edge is at most sqrt(3) delta_min long, a face covers at most 3 sqrt(3) / 4 delta_min^2 and a
// mesh has about two faces a vertex (an estimate: declined midpoints leave a few edges longer).
void requireFewEnoughVertices(const TriMesh& mesh, double delta, std::size_t maxVertices) {
  double area = 0;
  for (const auto f : mesh.faces())
    area += mesh.calc_face_area(f);
  const double needed = area / (2 * 3 * std::sqrt(3.0) / 4 * delta * delta);
  if (needed > double(maxVertices))
    throw PointInsertError("delta_min " + std::to_string(delta) + " would need about " +
                           std::to_string(std::llround(std::min(needed, 1e18))) +
                           " vertices, more than " + std::to_string(maxVertices) +
                           "; raise delta_min");
}

}  // namespace

PointInsertResult insertPoints(const TriMesh& mesh, const PointInsertOptions& options) {
  const double delta = options.deltaMin;
  if (!(delta > 0) || !std::isfinite(delta))
    throw PointInsertError("delta_min must be a positive number");
  const double half = delta / 2;
  requireRepresentable(mesh, half);
  requireFewEnoughVertices(mesh, delta, options.maxVertices);
  PointInsertResult result;
  result.mesh = mesh;
  TriMesh& out = result.mesh;
  SpacingGrid grid(half);
  for (const auto v : out.vertices())
    grid.add(toEigen(out.point(v)), v.idx());
  const std::size_t original = out.n_vertices();
  const double longest = std::sqrt(3.0) * delta;
  std::vector<char> declined(out.n_edges(), 0);
  for (bool split = true; split;) {
    split = false;
    for (const auto e : splitCandidates(out, longest, declined, options.splitBoundary)) {
      const auto h = out.halfedge_handle(e, 0);
      const Eigen::Vector3d mid = (toEigen(out.point(out.from_vertex_handle(h))) +
                                   toEigen(out.point(out.to_vertex_handle(h)))) /
                                  2;
      if (grid.nearest(mid, 1) < half) {
        declined[std::size_t(e.idx())] = 1;
        ++result.declined;
        continue;
      }
      if (out.n_vertices() >= options.maxVertices)
        throw PointInsertError("the refinement would pass " + std::to_string(options.maxVertices) +
                               " vertices; raise delta_min");
      const auto v = out.split(e, toPoint(mid));
      grid.add(mid, v.idx());
      declined.resize(out.n_edges(), 0);
      split = true;
    }
  }
  result.inserted = out.n_vertices() - original;
  result.closestInserted = closestInsertedDistance(out, original, grid);
  return result;
}

double borderSpacing(const TriMesh& mesh, const std::vector<int>& border) {
  std::vector<double> lengths;
  for (int v : border)
    for (const auto e : mesh.ve_range(TriMesh::VertexHandle(v)))
      lengths.push_back(mesh.calc_edge_length(e));
  if (lengths.empty()) throw PointInsertError("the border has no edges to measure");
  std::sort(lengths.begin(), lengths.end());
  const std::size_t n = lengths.size();
  return n % 2 ? lengths[n / 2] : (lengths[n / 2 - 1] + lengths[n / 2]) / 2;
}

}  // namespace geobrush
