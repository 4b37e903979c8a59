#include "geobrush/exponential_map.hpp"

#include "geobrush/parallel.hpp"
#include "geobrush/simd.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
#include <numeric>
#include <system_error>
#include <thread>
#include <utility>

namespace geobrush {
namespace {

std::vector<Eigen::Vector3d> points(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices())
    p.push_back(toEigen(mesh.point(v)));
  return p;
}

double boundingDiagonal(const std::vector<Eigen::Vector3d>& p) {
  if (p.empty()) return 0;
  Eigen::Vector3d lo = p.front(), hi = p.front();
  for (const auto& x : p) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return (hi - lo).norm();
}

// The corner vertices of every face, read once so that face loops avoid OpenMesh circulators.
std::vector<std::array<int, 3>> faceCorners(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> corners(mesh.n_faces());
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    for (int& corner : corners[f.idx()]) {
      corner = mesh.to_vertex_handle(h).idx();
      h = mesh.next_halfedge_handle(h);
    }
  }
  return corners;
}

// Exact at whole quarter turns, so that turning the axes by 90 degrees swaps u and v exactly.
std::pair<double, double> cosSinDegrees(double degrees) {
  const double reduced = std::remainder(degrees, 360.0);
  if (reduced == 0) return {1.0, 0.0};
  if (reduced == 90) return {0.0, 1.0};
  if (reduced == -90) return {0.0, -1.0};
  if (std::abs(reduced) == 180) return {-1.0, 0.0};
  const double radians = reduced * std::numbers::pi / 180;
  return {std::cos(radians), std::sin(radians)};
}

// The frame moved to `normal` by the smallest rotation taking frame.normal onto it.
Frame transport(const Frame& frame, const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d k = frame.normal.cross(normal);
  const double c = frame.normal.dot(normal);
  Eigen::Vector3d u = frame.uAxis;
  // Rodrigues' formula for the rotation about k; near a half turn it is ill-conditioned, and
  // projecting the axis onto the new tangent plane serves instead.
  if (1 + c > 1e-6) u = c * u + k.cross(u) + (k.dot(u) / (1 + c)) * k;
  u -= u.dot(normal) * normal;
  Frame moved;
  moved.point = point;
  moved.normal = normal;
  if (u.norm() > 1e-6) {
    moved.uAxis = u.normalized();
    moved.vAxis = normal.cross(moved.uAxis);
  } else {
    Eigen::Vector3d v = frame.vAxis - frame.vAxis.dot(normal) * normal;
    moved.vAxis = v.normalized();
    moved.uAxis = moved.vAxis.cross(normal);
  }
  return moved;
}

// The step from q to p expressed in q's frame.
Eigen::Vector2d step(const Frame& q, const Eigen::Vector3d& p, bool rescale) {
  const Eigen::Vector3d d = p - q.point;
  Eigen::Vector2d s(q.uAxis.dot(d), q.vAxis.dot(d));
  const double projected = s.norm();
  // A step along the normal has no tangent direction to rescale.
  if (rescale && projected > 1e-12 * d.norm()) s *= d.norm() / projected;
  return s;
}

// A symmetric graph in compressed rows: the neighbours of v are
// neighbour[first[v]] .. neighbour[first[v + 1] - 1].
struct Adjacency {
  std::vector<int> first;
  std::vector<int> neighbour;
};

// The graph with an edge each way for every pair that forEachPair(add) passes to add(a, b), each
// row in the order of the first mention of its entries. forEachPair runs twice: once to count the
// rows, once to fill them.
template <typename ForEachPair>
Adjacency symmetricAdjacency(std::size_t vertexCount, int threads, const ForEachPair& forEachPair) {
  Adjacency graph;
  graph.first.assign(vertexCount + 1, 0);
  forEachPair([&](int a, int b) {
    ++graph.first[a + 1];
    ++graph.first[b + 1];
  });
  std::partial_sum(graph.first.begin(), graph.first.end(), graph.first.begin());
  std::vector<int> end(graph.first.begin(), graph.first.end() - 1);
  graph.neighbour.resize(graph.first.back());
  forEachPair([&](int a, int b) {
    graph.neighbour[end[a]++] = b;
    graph.neighbour[end[b]++] = a;
  });
  // Each row keeps the first of its repeats, found by stamping its entries with the row (cheaper
  // than sorting the short rows); then the rows move together.
  parallelBlocks(vertexCount, 8192, threads, [&](std::size_t first, std::size_t last) {
    std::vector<int> stamp(vertexCount, -1);
    for (std::size_t v = first; v < last; ++v) {
      int kept = graph.first[v];
      for (int e = graph.first[v]; e < end[v]; ++e) {
        const int w = graph.neighbour[e];
        if (stamp[w] == int(v)) continue;
        stamp[w] = int(v);
        graph.neighbour[kept++] = w;
      }
      end[v] = kept;
    }
  });
  int kept = 0;
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const int begin = graph.first[v];
    graph.first[v] = kept;
    for (int e = begin; e < end[v]; ++e)
      graph.neighbour[std::size_t(kept++)] = graph.neighbour[std::size_t(e)];
  }
  graph.first[vertexCount] = kept;
  graph.neighbour.resize(std::size_t(kept));
  return graph;
}

template <typename Add>
void forEachMeshEdge(const TriMesh& mesh, const Add& add) {
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    add(mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx());
  }
}

// The boundary samples of Eq. 1 as a structure of arrays, so that its sum runs over whole lanes.
// The padding up to a whole lane lies at infinity with a zero normal: its weight and term are
// exactly 0.
struct BoundaryNormals {
  static constexpr int kLanes = 4;
  Eigen::ArrayXd x, y, z, nx, ny, nz;
};

BoundaryNormals boundaryNormals(const std::vector<Eigen::Vector3d>& p,
                                const std::vector<int>& boundary,
                                const std::vector<Eigen::Vector3d>& normals) {
  const auto count = Eigen::Index(boundary.size());
  const Eigen::Index padded =
      (count + BoundaryNormals::kLanes - 1) / BoundaryNormals::kLanes * BoundaryNormals::kLanes;
  const double far = std::numeric_limits<double>::infinity();
  BoundaryNormals b;
  for (Eigen::ArrayXd* a : {&b.x, &b.y, &b.z})
    a->setConstant(padded, far);
  for (Eigen::ArrayXd* a : {&b.nx, &b.ny, &b.nz})
    a->setZero(padded);
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Vector3d& w = p[boundary[i]];
    const Eigen::Vector3d& n = normals[boundary[i]];
    b.x[i] = w.x();
    b.y[i] = w.y();
    b.z[i] = w.z();
    b.nx[i] = n.x();
    b.ny[i] = n.y();
    b.nz[i] = n.z();
  }
  return b;
}

struct WeightedSum {
  Eigen::Vector3d normal;
  double weight = 0;
};

// Eq. 1 at v: the sum of n(w) / (|w - v|^2 + eps) over the boundary samples w, and the sum of
// the weights. Lane j sums the samples j, j + 4, ...; the lanes are added in a fixed order, so
// the result depends on v alone. Four lanes fill one AVX2 register under simd::fastest, two
// SSE2 registers elsewhere: the same operations on the same lanes.
[[gnu::always_inline]] inline WeightedSum equationOneSum(const BoundaryNormals& b,
                                                         const Eigen::Vector3d& v, double eps) {
  static_assert(BoundaryNormals::kLanes == 4);
  using FourLanes = double __attribute__((vector_size(4 * sizeof(double))));
  FourLanes sumX = {}, sumY = {}, sumZ = {}, sumW = {};
  FourLanes x, y, z, nx, ny, nz;
  for (Eigen::Index i = 0; i < b.x.size(); i += 4) {
    std::memcpy(&x, b.x.data() + i, sizeof x);
    std::memcpy(&y, b.y.data() + i, sizeof y);
    std::memcpy(&z, b.z.data() + i, sizeof z);
    std::memcpy(&nx, b.nx.data() + i, sizeof nx);
    std::memcpy(&ny, b.ny.data() + i, sizeof ny);
    std::memcpy(&nz, b.nz.data() + i, sizeof nz);
    const FourLanes dx = x - v.x(), dy = y - v.y(), dz = z - v.z();
    const FourLanes w = 1.0 / (dx * dx + dy * dy + dz * dz + eps);
    sumX += w * nx;
    sumY += w * ny;
    sumZ += w * nz;
    sumW += w;
  }
  auto total = [](const FourLanes& l) { return (l[0] + l[1]) + (l[2] + l[3]); };
  return {{total(sumX), total(sumY), total(sumZ)}, total(sumW)};
}

// `items` sorted stably by key(item) in [0, keyCount), and where each key's run starts
// (keyCount + 1 entries).
template <typename Key>
std::pair<std::vector<int>, std::vector<int>> countingSort(const std::vector<int>& items,
                                                           int keyCount, const Key& key) {
  std::vector<int> start(std::size_t(keyCount) + 1, 0);
  for (int item : items)
    ++start[std::size_t(key(item)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> sorted(items.size());
  std::vector<int> next(start.begin(), start.end() - 1);
  for (int item : items)
    sorted[std::size_t(next[std::size_t(key(item))]++)] = item;
  return {std::move(sorted), std::move(start)};
}

// A uniform grid of cubic cells over points, stored column by column: the points of each (x, y)
// column sorted by z cell, then by index, so that the cells z0..z1 of a column are one run.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3d>& p, double cellSize) : cellSize_(cellSize) {
    Eigen::Vector3d hi = p.front();
    lo_ = p.front();
    for (const auto& x : p) {
      lo_ = lo_.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    dims_ = ((hi - lo_) / cellSize_).array().floor().cast<int>() + 1;
    std::vector<int> column(p.size()), zCell(p.size()), all(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Eigen::Array3i c = cellOf(p[i]);
      column[i] = c.x() * dims_.y() + c.y();
      zCell[i] = c.z();
      all[i] = int(i);
    }
    // Two stable passes (z cell, then column) order the points by (column, z cell, index).
    const auto byZ = countingSort(all, dims_.z(), [&](int i) { return zCell[i]; }).first;
    std::tie(point_, columnStart_) =
        countingSort(byZ, dims_.x() * dims_.y(), [&](int i) { return column[i]; });
    zCell_.resize(p.size());
    for (std::size_t e = 0; e < point_.size(); ++e)
      zCell_[e] = zCell[point_[e]];
  }

  double cellSize() const { return cellSize_; }
  const Eigen::Array3i& dims() const { return dims_; }
  Eigen::Array3i cellOf(const Eigen::Vector3d& x) const {
    return ((x - lo_) / cellSize_).array().floor().cast<int>().min(dims_ - 1).max(0);
  }

  // A non-empty cell: its grid index and the run of entries holding its points.
  struct Cell {
    Eigen::Array3i index;
    int begin, end;
  };
  std::vector<Cell> cells() const {
    std::vector<Cell> cells;
    for (int column = 0; column + 1 < int(columnStart_.size()); ++column) {
      for (int e = columnStart_[column]; e < columnStart_[column + 1]; ++e) {
        if (e > columnStart_[column] && zCell_[e] == zCell_[e - 1]) continue;
        cells.push_back({{column / dims_.y(), column % dims_.y(), zCell_[e]}, e, e});
      }
    }
    // The entries run on from cell to cell.
    for (std::size_t c = 0; c < cells.size(); ++c)
      cells[c].end = c + 1 < cells.size() ? cells[c + 1].begin : int(point_.size());
    return cells;
  }
  int pointOfEntry(int e) const { return point_[e]; }

  // Calls visit(j) for every point j in the cells (x, y, z0..z1), clipped to the grid.
  template <typename Visit>
  void visitColumn(int x, int y, int z0, int z1, const Visit& visit) const {
    if (x < 0 || y < 0 || x >= dims_.x() || y >= dims_.y()) return;
    const std::size_t column = std::size_t(x) * std::size_t(dims_.y()) + std::size_t(y);
    const auto begin = zCell_.begin() + columnStart_[column];
    const auto end = zCell_.begin() + columnStart_[column + 1];
    for (auto e = std::lower_bound(begin, end, z0); e != end && *e <= z1; ++e)
      visit(point_[std::size_t(e - zCell_.begin())]);
  }

 private:
  double cellSize_;
  Eigen::Vector3d lo_;
  Eigen::Array3i dims_;
  std::vector<int> point_, zCell_;  // grid entries, column by column
  std::vector<int> columnStart_;    // per column (x * dims.y + y), its first entry
};

// Calls visit(j) for every point j in the cells at Chebyshev distance exactly r from `home`.
template <typename Visit>
void visitShell(const PointGrid& grid, const Eigen::Array3i& home, int r, const Visit& visit) {
  for (int x = home.x() - r; x <= home.x() + r; ++x) {
    for (int y = home.y() - r; y <= home.y() + r; ++y) {
      if (std::abs(x - home.x()) == r || std::abs(y - home.y()) == r) {
        grid.visitColumn(x, y, home.z() - r, home.z() + r, visit);
      } else {
        grid.visitColumn(x, y, home.z() - r, home.z() - r, visit);
        grid.visitColumn(x, y, home.z() + r, home.z() + r, visit);
      }
    }
  }
}

// The k nearest other points of every point, perPoint = min(k, n - 1) in a row each.
struct NeighbourTable {
  std::size_t perPoint = 0;
  std::vector<int> index;
};

// The `want` nearest of the points offered, as (squared distance, index) pairs in increasing
// order: a strict order, so the result does not depend on the order of the offers.
class NearestList {
 public:
  explicit NearestList(std::size_t want) : want_(want) { best_.reserve(want + 1); }
  void clear() { best_.clear(); }
  void offer(double squaredDistance, int index) {
    const std::pair<double, int> candidate{squaredDistance, index};
    if (full() && !(candidate < best_.back())) return;
    best_.insert(std::upper_bound(best_.begin(), best_.end(), candidate), candidate);
    if (best_.size() > want_) best_.pop_back();
  }
  bool full() const { return best_.size() == want_; }
  // Whether every point farther than `distance` from the query is surely not among the nearest.
  bool settledWithin(double distance) const {
    return full() && best_.back().first <= distance * distance;
  }
  void write(int* out) const {
    for (const auto& [d, j] : best_)
      *out++ = j;
  }

 private:
  std::size_t want_;
  std::vector<std::pair<double, int>> best_;
};

// Offers `nearest` the points of the shells from `firstShell` on around point i's cell `home`,
// until its k-th nearest is nearer than every shell not searched.
void searchShells(const PointGrid& grid, const std::vector<Eigen::Vector3d>& p, int i,
                  const Eigen::Array3i& home, int firstShell, NearestList& nearest) {
  const int maxRing = grid.dims().maxCoeff();
  for (int r = firstShell; r <= maxRing; ++r) {
    // Points beyond shell r - 1 are at least (r - 1) * h away.
    if (r > 0 && nearest.settledWithin((r - 1) * grid.cellSize())) return;
    visitShell(grid, home, r, [&](int j) {
      if (j != i) nearest.offer((p[j] - p[i]).squaredNorm(), j);
    });
  }
}

// The points of one grid cell share the first search, of the 27 cells around it, which settles
// nearly all of them; the others search on alone. Cells are independent, so threads share them.
NeighbourTable nearestNeighbourTable(const std::vector<Eigen::Vector3d>& p, int k, int threads) {
  const std::size_t n = p.size();
  NeighbourTable table;
  if (n < 2 || k < 1) return table;
  table.perPoint = std::min<std::size_t>(static_cast<std::size_t>(k), n - 1);
  table.index.resize(n * table.perPoint);
  // About a few points per cell for points spread over a surface.
  const double diagonal = boundingDiagonal(p);
  const PointGrid grid(p, diagonal > 0 ? 2 * diagonal / std::sqrt(static_cast<double>(n)) : 1.0);
  const auto cells = grid.cells();
  parallelBlocks(cells.size(), 64, threads, [&](std::size_t first, std::size_t last) {
    NearestList nearest(table.perPoint);
    std::vector<Eigen::Vector3d> blockPoint;
    std::vector<int> blockIndex;
    for (std::size_t c = first; c < last; ++c) {
      const Eigen::Array3i& home = cells[c].index;
      blockPoint.clear();
      blockIndex.clear();
      for (int r = 0; r <= 1; ++r) {
        visitShell(grid, home, r, [&](int j) {
          blockPoint.push_back(p[j]);
          blockIndex.push_back(j);
        });
      }
      for (int e = cells[c].begin; e < cells[c].end; ++e) {
        const int i = grid.pointOfEntry(e);
        nearest.clear();
        for (std::size_t m = 0; m < blockIndex.size(); ++m)
          if (blockIndex[m] != i)
            nearest.offer((blockPoint[m] - p[i]).squaredNorm(), blockIndex[m]);
        searchShells(grid, p, i, home, 2, nearest);
        nearest.write(&table.index[std::size_t(i) * table.perPoint]);
      }
    }
  });
  return table;
}

// Whether slot a comes before slot b in the propagation: by distance, ties by vertex id.
bool nearer(int a, int b, const std::vector<double>& distance, const std::vector<int>& vertex) {
  return distance[a] < distance[b] || (distance[a] == distance[b] && vertex[a] < vertex[b]);
}

// The DEM propagation (see `propagate`) over the canvas vertices `p`, with neighbours(v, out)
// appending the neighbours of v.
std::vector<Eigen::Vector2d> propagateOver(const Canvas& canvas,
                                           const std::vector<Eigen::Vector3d>& p,
                                           const std::vector<Eigen::Vector3d>& normals,
                                           const Frame& origin,
                                           std::function<void(int, std::vector<int>&)> neighbours,
                                           bool rescale) {
  const std::size_t n = p.size();
  std::vector<int> originCorners;
  for (auto v : canvas.surface.fv_range(TriMesh::FaceHandle(canvas.originFace)))
    originCorners.push_back(v.idx());
  ExponentialMapGrowth::Graph graph;
  graph.vertexCount = n;
  graph.point = [&](int v) { return p[v]; };
  graph.normal = [&](int v) { return normals[v]; };
  graph.neighbours = std::move(neighbours);
  ExponentialMapGrowth growth(
      std::move(graph), origin, originCorners, rescale,
      1e-12 * std::max(boundingDiagonal(p), std::numeric_limits<double>::min()));
  while (growth.fixNext() >= 0) {
  }
  std::vector<Eigen::Vector2d> uv(n, Eigen::Vector2d::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    if (!growth.isFixed(static_cast<int>(i))) {
      throw DemError("canvas",
                     "canvas vertex " + std::to_string(i) + " is not connected to the origin");
    }
    uv[i] = growth.uv(static_cast<int>(i));
  }
  return uv;
}

void checkCanvas(const Canvas& canvas) {
  const TriMesh& s = canvas.surface;
  if (s.n_faces() == 0) throw DemError("canvas", "the canvas has no faces");
  if (canvas.boundary.empty()) {
    throw DemError("canvas", "the canvas has no boundary loop (Eq. 1 needs its normals)");
  }
  for (int b : canvas.boundary) {
    if (b < 0 || b >= static_cast<int>(s.n_vertices())) {
      throw DemError("canvas", "boundary vertex " + std::to_string(b) + " is not on the canvas");
    }
  }
  if (canvas.originFace < 0 || canvas.originFace >= static_cast<int>(s.n_faces())) {
    throw DemError("canvas", "the canvas origin face " + std::to_string(canvas.originFace) +
                                 " is not on the canvas");
  }
  if (!canvas.originPoint.allFinite()) {
    throw DemError("canvas", "the canvas origin point is not finite");
  }
  if (canvas.source && canvas.sourceVertex.size() != s.n_vertices()) {
    throw DemError("canvas", "the canvas's source vertex map does not match its surface");
  }
  for (auto v : s.vertices()) {
    if (!toEigen(s.point(v)).allFinite()) {
      throw DemError("canvas", "canvas vertex " + std::to_string(v.idx()) + " is not finite");
    }
  }
}

void checkOptions(const DemOptions& o) {
  if (!std::isfinite(o.angleDegrees)) throw DemError("angle", "must be a finite number");
  if (o.neighbours < 1) throw DemError("neighbours", "must be at least 1");
  if (!std::isfinite(o.epsilon) || o.epsilon <= 0) {
    throw DemError("epsilon", "must be a finite number > 0");
  }
  if (!std::isfinite(o.reversedThreshold)) {
    throw DemError("reversed_threshold", "must be a finite number");
  }
  if (o.reversedRing < 0) throw DemError("reversed_ring", "must be 0 or more");
  if (o.threads < 0) throw DemError("threads", "must be 0 (one per hardware thread) or more");
}

// The unit surface normals (see surfaceNormals) at the canvas vertices `at`, zero elsewhere.
// Throws DemError("canvas") for the first of them that has none.
std::vector<Eigen::Vector3d> surfaceNormalsAt(const Canvas& canvas, const std::vector<int>& at,
                                              int threads) {
  const bool fromSource = canvas.source != nullptr;
  const TriMesh& mesh = fromSource ? canvas.source->surface : canvas.surface;
  std::vector<Eigen::Vector3d> normals(canvas.surface.n_vertices(), Eigen::Vector3d::Zero());
  std::vector<char> missing(at.size(), 0);
  parallelBlocks(at.size(), 1024, threads, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const int i = at[k];
      const int v = fromSource ? canvas.sourceVertex[i] : i;
      const Eigen::Vector3d n = angleWeightedNormal(mesh, TriMesh::VertexHandle(v));
      missing[k] = !(n.norm() > 0);
      if (!missing[k]) normals[i] = n.normalized();
    }
  });
  const auto bad = std::find(missing.begin(), missing.end(), 1);
  if (bad != missing.end()) {
    throw DemError("canvas", "canvas vertex " + std::to_string(at[bad - missing.begin()]) +
                                 " has no surface normal (its faces are degenerate or cancel "
                                 "out)");
  }
  return normals;
}

// Section 4.5's flags (see reversedFaces) over the faces' `corners` on the points `p`.
std::vector<std::uint8_t> reversedFlags(const std::vector<std::array<int, 3>>& corners,
                                        const std::vector<Eigen::Vector3d>& p,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        double threshold) {
  std::vector<std::uint8_t> flags(corners.size(), 0);
  for (std::size_t f = 0; f < corners.size(); ++f) {
    const auto& [a, b, c] = corners[f];
    const Eigen::Vector3d dem = normals[a] + normals[b] + normals[c];
    const Eigen::Vector3d face = (p[b] - p[a]).cross(p[c] - p[a]);
    const double dot =
        face.norm() > 0 && dem.norm() > 0 ? face.normalized().dot(dem.normalized()) : 0.0;
    flags[f] = dot < threshold;
  }
  return flags;
}

// growFaceRing over the faces' `corners` on `vertexCount` vertices.
std::vector<std::uint8_t> grownFlags(const std::vector<std::array<int, 3>>& corners,
                                     std::size_t vertexCount, std::vector<std::uint8_t> flags,
                                     int rings) {
  std::vector<char> marked(vertexCount);
  for (int r = 0; r < rings; ++r) {
    std::fill(marked.begin(), marked.end(), 0);
    for (std::size_t f = 0; f < corners.size(); ++f)
      if (flags[f])
        for (int v : corners[f])
          marked[v] = 1;
    for (std::size_t f = 0; f < corners.size(); ++f)
      for (int v : corners[f])
        if (marked[v]) flags[f] = 1;
  }
  return flags;
}

// Eq. 1 (see interpolatedNormals) on the canvas points `p`.
std::vector<Eigen::Vector3d> equationOneNormals(const std::vector<Eigen::Vector3d>& p,
                                                const std::vector<int>& boundaryLoop,
                                                const std::vector<Eigen::Vector3d>& surface,
                                                double epsilon, int threads) {
  const double diagonal = boundingDiagonal(p);
  const double eps = epsilon * diagonal * diagonal;
  const BoundaryNormals boundary = boundaryNormals(p, boundaryLoop, surface);
  std::vector<char> onBoundary(p.size(), 0);
  for (int b : boundaryLoop)
    onBoundary[b] = 1;
  std::vector<Eigen::Vector3d> normals = surface;
  std::vector<char> cancelled(p.size(), 0);
  // Each vertex sums over the whole boundary: blocks of 64 keep the threads evenly loaded.
  parallelBlocks(p.size(), 64, threads, [&](std::size_t first, std::size_t last) {
    simd::fastest([&] {
      for (std::size_t i = first; i < last; ++i) {
        if (onBoundary[i]) continue;
        const WeightedSum sum = equationOneSum(boundary, p[i], eps);
        cancelled[i] = !(sum.normal.norm() > 1e-9 * sum.weight);
        if (!cancelled[i]) normals[i] = sum.normal.normalized();
      }
    });
  });
  const auto bad = std::find(cancelled.begin(), cancelled.end(), 1);
  if (bad != cancelled.end()) {
    throw DemError("canvas", "the canvas boundary's normals cancel out at canvas vertex " +
                                 std::to_string(bad - cancelled.begin()) +
                                 ": the canvas wraps too far around the surface for Eq. 1; "
                                 "paint a flatter canvas or use the original DEM");
  }
  return normals;
}

}  // namespace

Eigen::Vector3d angleWeightedNormal(const TriMesh& mesh, TriMesh::VertexHandle v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const Eigen::Vector3d p = toEigen(mesh.point(v));
  for (auto h : mesh.voh_range(v)) {
    if (mesh.is_boundary(h)) continue;
    const Eigen::Vector3d a = toEigen(mesh.point(mesh.to_vertex_handle(h))) - p;
    const Eigen::Vector3d b =
        toEigen(mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)))) - p;
    const Eigen::Vector3d n = a.cross(b);
    const double length = n.norm();
    if (length == 0) continue;
    sum += std::atan2(length, a.dot(b)) * n / length;
  }
  return sum;
}

std::vector<Eigen::Vector3d> surfaceNormals(const Canvas& canvas, int threads) {
  std::vector<int> all(canvas.surface.n_vertices());
  std::iota(all.begin(), all.end(), 0);
  return surfaceNormalsAt(canvas, all, threads);
}

std::vector<Eigen::Vector3d> interpolatedNormals(const Canvas& canvas,
                                                 const std::vector<Eigen::Vector3d>& surface,
                                                 double epsilon, int threads) {
  return equationOneNormals(points(canvas.surface), canvas.boundary, surface, epsilon, threads);
}

Frame originFrame(const Canvas& canvas, const std::vector<Eigen::Vector3d>& normals,
                  double angleDegrees) {
  const TriMesh& s = canvas.surface;
  std::array<Eigen::Vector3d, 3> corners, cornerNormals;
  int i = 0;
  for (auto v : s.fv_range(TriMesh::FaceHandle(canvas.originFace))) {
    corners[i] = toEigen(s.point(v));
    cornerNormals[i++] = normals[v.idx()];
  }
  return originFrame(corners, cornerNormals, canvas.originPoint, angleDegrees);
}

Frame originFrame(const std::array<Eigen::Vector3d, 3>& corners,
                  const std::array<Eigen::Vector3d, 3>& normals, const Eigen::Vector3d& point,
                  double angleDegrees) {
  const Eigen::Vector3d& a = corners[0];
  const Eigen::Vector3d& b = corners[1];
  const Eigen::Vector3d& d = corners[2];
  const Eigen::Vector3d faceNormal = (b - a).cross(d - a);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const double area2 = faceNormal.squaredNorm();
  if (area2 > 0) {
    // Barycentric weights of the origin point: sub-triangle areas over the face's.
    const Eigen::Vector3d& x = point;
    const double wa = (b - x).cross(d - x).dot(faceNormal) / area2;
    const double wb = (d - x).cross(a - x).dot(faceNormal) / area2;
    n = wa * normals[0] + wb * normals[1] + (1 - wa - wb) * normals[2];
  }
  if (!(n.norm() > 1e-9)) n = normals[0] + normals[1] + normals[2];
  if (!(n.norm() > 1e-9)) n = faceNormal;
  if (!(n.norm() > 0)) {
    throw DemError("canvas", "the face under the canvas origin has no normal");
  }
  n.normalize();

  Eigen::Vector3d reference = Eigen::Vector3d::UnitY() - n.y() * n;
  if (reference.norm() < 1e-6) reference = Eigen::Vector3d::UnitZ() - n.z() * n;
  reference.normalize();
  const auto [cosine, sine] = cosSinDegrees(angleDegrees);
  Frame frame;
  frame.point = point;
  frame.normal = n;
  frame.vAxis = (cosine * reference + sine * n.cross(reference)).normalized();
  frame.uAxis = frame.vAxis.cross(n);
  return frame;
}

std::vector<std::vector<int>> nearestNeighbours(const std::vector<Eigen::Vector3d>& p, int k,
                                                int threads) {
  const NeighbourTable table = nearestNeighbourTable(p, k, threads);
  std::vector<std::vector<int>> result(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto row = table.index.begin() + std::ptrdiff_t(i * table.perPoint);
    result[i].assign(row, row + std::ptrdiff_t(table.perPoint));
  }
  return result;
}

void ExponentialMapGrowth::SlotQueue::moveUp(int slot, const std::vector<double>& distance,
                                             const std::vector<int>& vertex) {
  std::size_t at = place[slot] >= 0 ? std::size_t(place[slot]) : heap.size();
  if (at == heap.size()) heap.push_back(slot);
  for (; at > 0 && nearer(slot, heap[(at - 1) / 2], distance, vertex); at = (at - 1) / 2) {
    heap[at] = heap[(at - 1) / 2];
    place[heap[at]] = int(at);
  }
  heap[at] = slot;
  place[slot] = int(at);
}

int ExponentialMapGrowth::SlotQueue::popNearest(const std::vector<double>& distance,
                                                const std::vector<int>& vertex) {
  const int nearest = heap.front();
  place[nearest] = -1;
  const int last = heap.back();
  heap.pop_back();
  if (heap.empty()) return nearest;
  // The last slot sinks from the root.
  std::size_t at = 0;
  for (std::size_t child = 1; child < heap.size(); child = 2 * at + 1) {
    if (child + 1 < heap.size() && nearer(heap[child + 1], heap[child], distance, vertex)) ++child;
    if (!nearer(heap[child], last, distance, vertex)) break;
    heap[at] = heap[child];
    place[heap[at]] = int(at);
    at = child;
  }
  heap[at] = last;
  place[last] = int(at);
  return nearest;
}

ExponentialMapGrowth::ExponentialMapGrowth(Graph graph, const Frame& origin,
                                           const std::vector<int>& originCorners, bool rescale,
                                           double tiny)
    : graph_(std::move(graph)),
      origin_(origin),
      rescale_(rescale),
      tiny_(tiny),
      slot_(graph_.vertexCount, -1) {
  for (int v : originCorners) {
    const int s = slotOf(v);
    if (originCorner_[s]) continue;
    originCorner_[s] = 1;
    distance_[s] = (point_[s] - origin.point).norm();
    queue_.moveUp(s, distance_, vertex_);
  }
}

int ExponentialMapGrowth::slotOf(int vertex) {
  if (slot_[vertex] >= 0) return slot_[vertex];
  slot_[vertex] = static_cast<int>(vertex_.size());
  vertex_.push_back(vertex);
  distance_.push_back(std::numeric_limits<double>::infinity());
  parent_.push_back(-1);
  fixed_.push_back(0);
  originCorner_.push_back(0);
  point_.push_back(graph_.point(vertex));
  frame_.emplace_back();
  uv_.push_back(Eigen::Vector2d::Zero());
  queue_.place.push_back(-1);
  return slot_[vertex];
}

int ExponentialMapGrowth::fixNext() {
  if (queue_.heap.empty()) return -1;
  const int i = queue_.popNearest(distance_, vertex_);
  const int v = vertex_[i];
  const double d = distance_[i];
  const Eigen::Vector3d p = point_[i];
  frame_[i] = transport(parent_[i] < 0 ? origin_ : frame_[parent_[i]], p, graph_.normal(v));
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double weights = 0;
  auto average = [&](const Frame& q, const Eigen::Vector2d& uvq) {
    const double w = 1 / ((p - q.point).norm() + tiny_);
    sum += w * (uvq + step(q, p, rescale_));
    weights += w;
  };
  if (originCorner_[i]) average(origin_, Eigen::Vector2d::Zero());
  scratch_.clear();
  graph_.neighbours(v, scratch_);
  for (int w : scratch_) {
    const int j = slot_[w];
    if (j >= 0 && fixed_[j]) average(frame_[j], uv_[j]);
  }
  uv_[i] = sum / weights;
  fixed_[i] = 1;
  order_.push_back(v);
  for (int w : scratch_) {
    const int j = slotOf(w);
    if (fixed_[j]) continue;
    const double through = d + (point_[j] - p).norm();
    if (through < distance_[j]) {
      distance_[j] = through;
      parent_[j] = i;
      queue_.moveUp(j, distance_, vertex_);
    }
  }
  return v;
}

bool ExponentialMapGrowth::isFixed(int vertex) const {
  return slot_[vertex] >= 0 && fixed_[slot_[vertex]];
}

const Eigen::Vector2d& ExponentialMapGrowth::uv(int vertex) const {
  return uv_[slot_[vertex]];
}

const Eigen::Vector3d& ExponentialMapGrowth::normal(int vertex) const {
  return frame_[slot_[vertex]].normal;
}

std::vector<Eigen::Vector2d> propagate(const Canvas& canvas,
                                       const std::vector<Eigen::Vector3d>& normals,
                                       const Frame& origin,
                                       const std::vector<std::vector<int>>& adjacency,
                                       bool rescale) {
  return propagateOver(
      canvas, points(canvas.surface), normals, origin,
      [&](int v, std::vector<int>& out) {
        out.insert(out.end(), adjacency[v].begin(), adjacency[v].end());
      },
      rescale);
}

std::vector<std::uint8_t> reversedFaces(const TriMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        double threshold) {
  return reversedFlags(faceCorners(mesh), points(mesh), normals, threshold);
}

std::vector<std::uint8_t> growFaceRing(const TriMesh& mesh, std::vector<std::uint8_t> flags,
                                       int rings) {
  if (rings <= 0) return flags;
  return grownFlags(faceCorners(mesh), mesh.n_vertices(), std::move(flags), rings);
}

DemResult discreteExponentialMap(const Canvas& canvas, const DemOptions& options) {
  checkOptions(options);
  checkCanvas(canvas);
  DemResult result;
  const std::vector<Eigen::Vector3d> p = points(canvas.surface);
  // Eq. 1 reads the surface normals only on the boundary.
  result.normal =
      options.generalized
          ? equationOneNormals(p, canvas.boundary,
                               surfaceNormalsAt(canvas, canvas.boundary, options.threads),
                               options.epsilon, options.threads)
          : surfaceNormals(canvas, options.threads);
  result.origin = originFrame(canvas, result.normal, options.angleDegrees);

  NeighbourTable knn;
  // Section 4.2 propagates over k nearest neighbours; the mesh edges stay in so that every
  // vertex is reached even where the k-nearest-neighbour graph falls apart into clusters.
  if (options.generalized) knn = nearestNeighbourTable(p, options.neighbours, options.threads);
  const Adjacency adjacency = symmetricAdjacency(p.size(), options.threads, [&](const auto& add) {
    forEachMeshEdge(canvas.surface, add);
    for (std::size_t i = 0; i < knn.index.size(); ++i)
      add(int(i / knn.perPoint), knn.index[i]);
  });
  result.uv = propagateOver(
      canvas, p, result.normal, result.origin,
      [&](int v, std::vector<int>& out) {
        out.insert(out.end(), adjacency.neighbour.begin() + adjacency.first[v],
                   adjacency.neighbour.begin() + adjacency.first[v + 1]);
      },
      !options.generalized);
  for (std::size_t i = 0; i < result.uv.size(); ++i) {
    if (!result.uv[i].allFinite()) {
      throw DemError("canvas", "the map of canvas vertex " + std::to_string(i) +
                                   " is not finite (coincident vertices?)");
    }
  }
  const auto corners = faceCorners(canvas.surface);
  result.reversedFaces = grownFlags(
      corners, p.size(), reversedFlags(corners, p, result.normal, options.reversedThreshold),
      options.reversedRing);
  return result;
}

}  // namespace geobrush
