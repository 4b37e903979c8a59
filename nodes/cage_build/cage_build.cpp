#include "cage_build.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <span>

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// A uniform grid over the parameter domain; C is made of some of its cells.
struct Grid {
  Vector2d corner;  // position of grid vertex (0, 0)
  double step = 1;
  int cellsX = 0;
  int cellsY = 0;

  int cellIndex(int i, int j) const { return j * cellsX + i; }
  int vertexIndex(int i, int j) const { return j * (cellsX + 1) + i; }
  int vertexCount() const { return (cellsX + 1) * (cellsY + 1); }
  Vector2d vertex(int i, int j) const { return corner + step * Vector2d(i, j); }
  // The grid vertex whose Voronoi cell (the square of side `step` around it)
  // holds p; p must lie within the grid.
  int nearestVertex(const Vector2d& p) const {
    const Vector2d local = (p - corner) / step;
    return vertexIndex(int(std::lround(local.x())), int(std::lround(local.y())));
  }
};

Grid gridAround(const std::vector<Vector2d>& uv, int resolution) {
  Vector2d lo = uv.front(), hi = uv.front();
  for (const auto& p : uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-12);
  Grid grid;
  grid.step = extent / resolution;
  // Two free cells on every side: one for the dilation, one so that the
  // outside is connected around the region (a point exactly on the high side
  // falls into the next cell, hence one more there).
  grid.corner = lo - Vector2d::Constant(2 * grid.step);
  grid.cellsX = int(std::ceil((hi.x() - lo.x()) / grid.step)) + 5;
  grid.cellsY = int(std::ceil((hi.y() - lo.y()) / grid.step)) + 5;
  return grid;
}

// The cells C covers: every cell holding a canvas point, dilated by one cell,
// with holes filled and corner-only contacts closed, so that C is a disk.
std::vector<std::uint8_t> coveredCells(const Grid& grid, const std::vector<Vector2d>& uv) {
  const int nx = grid.cellsX, ny = grid.cellsY;
  std::vector<std::uint8_t> holds(std::size_t(nx) * ny, 0);
  for (const auto& p : uv) {
    const Vector2d local = (p - grid.corner) / grid.step;
    const int i = std::clamp(int(std::floor(local.x())), 0, nx - 1);
    const int j = std::clamp(int(std::floor(local.y())), 0, ny - 1);
    holds[grid.cellIndex(i, j)] = 1;
  }
  std::vector<std::uint8_t> covered(holds.size(), 0);
  for (int j = 1; j + 1 < ny; ++j)
    for (int i = 1; i + 1 < nx; ++i)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          if (holds[grid.cellIndex(i + di, j + dj)]) covered[grid.cellIndex(i, j)] = 1;

  for (bool changed = true; changed;) {
    changed = false;
    // Holes: free cells that the outside cannot reach.
    std::vector<std::uint8_t> outside(covered.size(), 0);
    std::deque<std::pair<int, int>> queue{{0, 0}};
    outside[0] = 1;
    while (!queue.empty()) {
      auto [i, j] = queue.front();
      queue.pop_front();
      const int next[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
      for (const auto& [a, b] : next) {
        if (a < 0 || b < 0 || a >= nx || b >= ny) continue;
        const int c = grid.cellIndex(a, b);
        if (covered[c] || outside[c]) continue;
        outside[c] = 1;
        queue.emplace_back(a, b);
      }
    }
    for (std::size_t c = 0; c < covered.size(); ++c)
      if (!covered[c] && !outside[c]) covered[c] = changed = true;
    // Two cells touching only at a corner would make C's boundary pinch.
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const int a = grid.cellIndex(i, j), b = grid.cellIndex(i + 1, j);
        const int c = grid.cellIndex(i, j + 1), d = grid.cellIndex(i + 1, j + 1);
        if ((covered[a] && covered[d] && !covered[b] && !covered[c]) ||
            (covered[b] && covered[c] && !covered[a] && !covered[d])) {
          covered[a] = covered[b] = covered[c] = covered[d] = 1;
          changed = true;
        }
      }
  }
  return covered;
}

// What C needs of the canvas at one of its vertices: a point on the line
// l(t) = point + t normal, the extremal projections, and the tangents.
struct Column {
  Vector3d point = Vector3d::Zero();
  Vector3d normal = Vector3d::Zero();
  Eigen::Matrix<double, 3, 2> tangents = Eigen::Matrix<double, 3, 2>::Zero();
  double low = 0;
  double high = 0;
  bool known = false;
};

// The canvas vertices as the cage needs them: their positions, and for
// every grid vertex the canvas vertices in its Voronoi cell.
struct CanvasSamples {
  std::vector<Vector3d> positions;
  std::vector<int> gridVertex;  // per canvas vertex
  std::vector<int> cellStart;   // per grid vertex g, its members start at members[cellStart[g]]
  std::vector<int> members;     // canvas vertices by grid vertex, each group in index order

  std::span<const int> cell(int g) const {
    return {members.data() + cellStart[g], members.data() + cellStart[g + 1]};
  }
};

CanvasSamples sampleCanvas(const Grid& grid, const Parameterization& param) {
  CanvasSamples samples;
  const TriMesh& surface = param.canvas->surface;
  const std::size_t n = surface.n_vertices();
  samples.positions.reserve(n);
  samples.gridVertex.reserve(n);
  samples.cellStart.assign(grid.vertexCount() + 1, 0);
  for (auto v : surface.vertices()) {
    samples.positions.push_back(toEigen(surface.point(v)));
    samples.gridVertex.push_back(grid.nearestVertex(param.uv[v.idx()]));
    ++samples.cellStart[samples.gridVertex.back() + 1];
  }
  // Counting sort by grid vertex.
  for (std::size_t g = 1; g < samples.cellStart.size(); ++g)
    samples.cellStart[g] += samples.cellStart[g - 1];
  samples.members.resize(n);
  std::vector<int> next(samples.cellStart.begin(), samples.cellStart.end() - 1);
  for (std::size_t v = 0; v < n; ++v)
    samples.members[next[samples.gridVertex[v]]++] = int(v);
  return samples;
}

// Fits p ~ point + tangents (w - u) to the canvas vertices around u (its
// Voronoi cell, for a uniform grid the square of side `step` around u, and
// the eight cells beside it, so that sparse canvases still give a plane),
// estimates the DEM normal n(u) over the same vertices, then takes the
// extremal projections of the cell's own vertices.
void fitColumn(Column& column, const Vector2d& u, const std::vector<int>& around,
               std::span<const int> own, const Parameterization& param,
               const CanvasSamples& samples) {
  // Least squares by the normal equations of the design matrix rows (1, w - u).
  Eigen::MatrixX3d basis(around.size(), 3), values(around.size(), 3);
  for (Eigen::Index r = 0; r < basis.rows(); ++r) {
    const int v = around[r];
    basis.row(r) << 1, (param.uv[v] - u).transpose();
    values.row(r) = samples.positions[v].transpose();
  }
  // Each product is nine dot products over the neighbourhood: evaluated
  // coefficient-wise, as GEMM's blocking and packing would cost more.
  const Eigen::Matrix3d normalMatrix = basis.transpose().lazyProduct(basis);
  const Eigen::Matrix3d rhs = basis.transpose().lazyProduct(values);
  // Collinear neighbourhoods leave the tangents to the neighbours' columns;
  // the point is then the mean.
  Eigen::LDLT<Eigen::Matrix3d> solver(normalMatrix);
  const double scale = normalMatrix.trace();
  column.known = around.size() >= 3 && solver.info() == Eigen::Success &&
                 std::abs(normalMatrix.determinant()) > 1e-12 * scale * scale * scale;
  if (column.known) {
    const Eigen::Matrix3d solution = solver.solve(rhs);
    column.point = solution.row(0).transpose();
    column.tangents.col(0) = solution.row(1).transpose();
    column.tangents.col(1) = solution.row(2).transpose();
  } else {
    column.point = rhs.row(0).transpose() / double(around.size());
  }
  // A cell of a sparse canvas holds only a few vertices: their normals alone
  // let neighbouring columns tilt against each other, and tall columns then
  // fold the shell.
  Vector3d normalSum = Vector3d::Zero();
  for (int v : around)
    normalSum += param.normal[v];
  column.normal = normalSum.normalized();
  column.low = std::numeric_limits<double>::infinity();
  column.high = -column.low;
  for (int v : own) {
    const double t = (samples.positions[v] - column.point).dot(column.normal);
    column.low = std::min(column.low, t);
    column.high = std::max(column.high, t);
  }
}

struct Domain {
  std::vector<Vector2d> positions;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::vector<int>> neighbours;
  std::vector<std::pair<int, int>> boundaryEdges;  // interior on the left
  std::vector<std::pair<int, int>> gridIndex;      // (i, j) of each vertex
};

Domain triangulate(const Grid& grid, const std::vector<std::uint8_t>& covered) {
  Domain domain;
  std::map<int, int> index;  // grid vertex -> domain vertex, in grid order
  auto vertex = [&](int i, int j) {
    auto [it, added] = index.emplace(grid.vertexIndex(i, j), int(domain.positions.size()));
    if (added) {
      domain.positions.push_back(grid.vertex(i, j));
      domain.gridIndex.emplace_back(i, j);
    }
    return it->second;
  };
  for (int j = 0; j < grid.cellsY; ++j)
    for (int i = 0; i < grid.cellsX; ++i) {
      if (!covered[grid.cellIndex(i, j)]) continue;
      const int a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1),
                d = vertex(i, j + 1);
      // Alternating diagonals keep C symmetric.
      if ((i + j) % 2 == 0) {
        domain.triangles.push_back({a, b, c});
        domain.triangles.push_back({a, c, d});
      } else {
        domain.triangles.push_back({a, b, d});
        domain.triangles.push_back({b, c, d});
      }
    }
  std::map<std::pair<int, int>, int> edgeCount;
  domain.neighbours.resize(domain.positions.size());
  for (const auto& t : domain.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edgeCount[{a, b}];
      domain.neighbours[a].push_back(b);
      domain.neighbours[b].push_back(a);
    }
  for (auto& list : domain.neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  for (const auto& [edge, count] : edgeCount)
    if (!edgeCount.count({edge.second, edge.first})) domain.boundaryEdges.push_back(edge);
  return domain;
}

// Columns for every domain vertex: fitted where the canvas is, and carried
// outward (first-order: point + tangents * offset) to the vertices beyond it.
std::vector<Column> columns(const Grid& grid, const Domain& domain, const Parameterization& param,
                            const CanvasSamples& samples) {
  std::vector<Column> result(domain.positions.size());
  std::vector<std::uint8_t> placed(result.size(), 0);
  std::vector<int> around;
  for (std::size_t d = 0; d < result.size(); ++d) {
    const auto [i, j] = domain.gridIndex[d];
    const std::span<const int> own = samples.cell(grid.vertexIndex(i, j));
    if (own.empty()) continue;
    // Canvas vertices lie two cells inside the grid, so the neighbours exist.
    around.clear();
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const std::span<const int> cell = samples.cell(grid.vertexIndex(i + di, j + dj));
        around.insert(around.end(), cell.begin(), cell.end());
      }
    fitColumn(result[d], domain.positions[d], around, own, param, samples);
    placed[d] = 1;
  }
  // Tangents where the neighbourhood was too thin: the mean of the
  // neighbours', spreading ring by ring over the whole domain.
  if (std::none_of(result.begin(), result.end(), [](const Column& c) { return c.known; }))
    throw CageBuildError("too few canvas vertices to find a tangent plane anywhere");
  for (bool progress = true; progress;) {
    progress = false;
    std::vector<std::size_t> filled;
    for (std::size_t d = 0; d < result.size(); ++d) {
      if (result[d].known) continue;
      Eigen::Matrix<double, 3, 2> sum = Eigen::Matrix<double, 3, 2>::Zero();
      int count = 0;
      for (int n : domain.neighbours[d])
        if (result[n].known) {
          sum += result[n].tangents;
          ++count;
        }
      if (!count) continue;
      result[d].tangents = sum / count;
      filled.push_back(d);
    }
    for (std::size_t d : filled)
      result[d].known = progress = true;
  }
  // Breadth-first outward from the placed columns, in a fixed order.
  std::deque<int> queue;
  for (std::size_t d = 0; d < result.size(); ++d)
    if (placed[d]) queue.push_back(int(d));
  while (!queue.empty()) {
    const int d = queue.front();
    queue.pop_front();
    for (int n : domain.neighbours[d]) {
      if (placed[n]) continue;
      Column sum;
      int count = 0;
      for (int m : domain.neighbours[n]) {
        if (!placed[m]) continue;
        const Column& c = result[m];
        sum.point += c.point + c.tangents * (domain.positions[n] - domain.positions[m]);
        sum.normal += c.normal;
        sum.low += c.low;
        sum.high += c.high;
        ++count;
      }
      Column& column = result[n];
      column.point = sum.point / count;
      column.normal = sum.normal.normalized();
      column.low = sum.low / count;
      column.high = sum.high / count;
      placed[n] = 1;
      queue.push_back(n);
    }
  }
  return result;
}

TriMesh shellMesh(const Domain& domain, const std::vector<Column>& columns, double margin,
                  const std::vector<double>& raise, const std::vector<double>& lower,
                  std::vector<int>& top, std::vector<int>& bottom) {
  TriMesh mesh;
  const int n = int(domain.positions.size());
  top.resize(n);
  bottom.resize(n);
  for (int d = 0; d < n; ++d) {
    const Column& c = columns[d];
    const Vector3d up = c.point + (c.high + margin + raise[d]) * c.normal;
    const Vector3d down = c.point + (c.low - margin - lower[d]) * c.normal;
    top[d] = mesh.add_vertex(toPoint(up)).idx();
    bottom[d] = mesh.add_vertex(toPoint(down)).idx();
  }
  auto vh = [](int i) { return TriMesh::VertexHandle(i); };
  for (const auto& t : domain.triangles) {
    mesh.add_face(vh(top[t[0]]), vh(top[t[1]]), vh(top[t[2]]));
    mesh.add_face(vh(bottom[t[0]]), vh(bottom[t[2]]), vh(bottom[t[1]]));
  }
  for (const auto& [a, b] : domain.boundaryEdges) {
    mesh.add_face(vh(top[a]), vh(bottom[a]), vh(bottom[b]));
    mesh.add_face(vh(top[a]), vh(bottom[b]), vh(top[b]));
  }
  return mesh;
}

// Laplacian mesh optimization [NISA06]: min |L x|^2 + w^2 |x - x0|^2 with the
// uniform graph Laplacian, solved once for x, y and z. Every attempt builds
// a shell with the same connectivity, so L^T L and its sparsity analysis are
// made once, and the factorization is redone only when the weight changes.
class ShellSmoother {
 public:
  explicit ShellSmoother(const TriMesh& shell) {
    const int n = int(shell.n_vertices());
    std::vector<Eigen::Triplet<double>> entries;
    for (auto v : shell.vertices()) {
      const double valence = double(shell.valence(v));
      entries.emplace_back(v.idx(), v.idx(), 1.0);
      for (auto w : shell.vv_range(v))
        entries.emplace_back(v.idx(), w.idx(), -1.0 / valence);
    }
    Eigen::SparseMatrix<double> laplacian(n, n);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    smoothness_ = laplacian.transpose() * laplacian;
    identity_.resize(n, n);
    identity_.setIdentity();
    // L^T L has a full diagonal, so adding w^2 I keeps its pattern.
    solver_.analyzePattern(smoothness_);
  }

  void smooth(TriMesh& mesh, double weight) {
    if (weight != factoredWeight_) {
      solver_.factorize(smoothness_ + weight * weight * identity_);
      if (solver_.info() != Eigen::Success)
        throw CageBuildError("the cage smoothing system is singular");
      factoredWeight_ = weight;
    }
    Eigen::MatrixX3d anchors(mesh.n_vertices(), 3);
    for (auto v : mesh.vertices())
      anchors.row(v.idx()) = toEigen(mesh.point(v)).transpose();
    const Eigen::MatrixX3d smoothed = solver_.solve(weight * weight * anchors);
    for (auto v : mesh.vertices()) {
      const auto row = smoothed.row(v.idx());
      mesh.point(v) = {row.x(), row.y(), row.z()};
    }
  }

 private:
  Eigen::SparseMatrix<double> smoothness_;  // L^T L
  Eigen::SparseMatrix<double> identity_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
  double factoredWeight_ = std::numeric_limits<double>::quiet_NaN();
};

double signedVolume(const TriMesh& mesh) {
  double volume = 0;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_begin(f);
    const Vector3d a = toEigen(mesh.point(*it));
    const Vector3d b = toEigen(mesh.point(*++it));
    const Vector3d c = toEigen(mesh.point(*++it));
    volume += a.dot(b.cross(c)) / 6;
  }
  return volume;
}

// The frames decide the handedness of (u, v, n); the cage must face outward.
void orientOutward(TriMesh& mesh) {
  if (signedVolume(mesh) >= 0) return;
  TriMesh flipped;
  for (auto v : mesh.vertices())
    flipped.add_vertex(mesh.point(v));
  for (auto f : mesh.faces()) {
    std::vector<TriMesh::VertexHandle> ids(mesh.fv_begin(f), mesh.fv_end(f));
    flipped.add_face(ids[0], ids[2], ids[1]);
  }
  mesh = std::move(flipped);
}

bool segmentHitsTriangle(const Vector3d& p, const Vector3d& q, const Vector3d& a, const Vector3d& b,
                         const Vector3d& c) {
  // Moeller-Trumbore on the segment p + s (q - p), s in [0, 1].
  const Vector3d dir = q - p, e1 = b - a, e2 = c - a;
  const Vector3d h = dir.cross(e2);
  const double det = e1.dot(h);
  const double scale = e1.norm() * e2.norm() * dir.norm();
  if (std::abs(det) <= 1e-12 * scale) return false;  // parallel: coplanar overlaps are not counted
  const Vector3d s = p - a;
  const double u = s.dot(h) / det;
  if (u < 0 || u > 1) return false;
  const Vector3d qv = s.cross(e1);
  const double v = dir.dot(qv) / det;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(qv) / det;
  return t >= 0 && t <= 1;
}

}  // namespace

double windingNumber(const TriMesh& mesh, const Vector3d& point) {
  double total = 0;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_begin(f);
    // Van Oosterom and Strackee's solid angle of a triangle seen from `point`.
    const Vector3d a = toEigen(mesh.point(*it)) - point;
    const Vector3d b = toEigen(mesh.point(*++it)) - point;
    const Vector3d c = toEigen(mesh.point(*++it)) - point;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(numerator, denominator);
  }
  return total / (4 * M_PI);
}

// Distances below this fraction of the mesh's size are too close to call by
// crossings: far above the rounding of the predicates (a few 1e-16 of it),
// far below any clearance a cage keeps.
constexpr double kEnclosureTolerance = 1e-9;

EnclosureTest::EnclosureTest(const TriMesh& closedMesh) : mesh_(closedMesh) {
  for (auto h : mesh_.halfedges())
    if (mesh_.is_boundary(h)) throw std::invalid_argument("the enclosure test needs a closed mesh");
  for (auto f : mesh_.faces()) {
    Triangle triangle;
    int k = 0;
    for (auto v : mesh_.fv_range(f)) {
      triangle.corners[k] = toEigen(mesh_.point(v));
      triangle.box.extend(triangle.corners[k++]);
    }
    const auto& [a, b, c] = triangle.corners;
    triangle.normal = (b - a).cross(c - a);
    triangles_.push_back(triangle);
    bounds_.extend(triangle.box);
  }
  tolerance_ = kEnclosureTolerance * bounds_.diagonal().norm();
  // No faces (an empty box's diagonal is infinite, not zero), or all of them in one point:
  // encloses nothing.
  if (triangles_.empty() || !(tolerance_ > 0)) {
    triangles_.clear();
    bounds_.setEmpty();
    return;
  }
  bounds_.extend(bounds_.min() - Vector3d::Constant(tolerance_));
  bounds_.extend(bounds_.max() + Vector3d::Constant(tolerance_));

  // The ray runs along the axis whose perpendicular plane the triangles'
  // boxes cover least often: each point then tests the fewest triangles.
  double fewest = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    double covered = 0;
    for (const auto& t : triangles_)
      covered += t.box.sizes()[u] * t.box.sizes()[v];
    const double cover = covered / (bounds_.sizes()[u] * bounds_.sizes()[v]);
    if (cover < fewest) {
      fewest = cover;
      axis_ = axis;
    }
  }
  u_ = (axis_ + 1) % 3;
  v_ = (axis_ + 2) % 3;
  binTriangles();
}

// About four cells per triangle over the box's projection, each listing the
// triangles whose grown boxes overlap it.
void EnclosureTest::binTriangles() {
  const double sizeU = bounds_.sizes()[u_], sizeV = bounds_.sizes()[v_];
  cellSize_ = std::sqrt(sizeU * sizeV / (4.0 * double(triangles_.size())));
  constexpr int kMaxCellsPerSide = 1024;  // bounds the grid of a very elongated mesh
  cellsU_ = std::clamp(int(std::ceil(sizeU / cellSize_)), 1, kMaxCellsPerSide);
  cellsV_ = std::clamp(int(std::ceil(sizeV / cellSize_)), 1, kMaxCellsPerSide);
  auto forCells = [&](const Triangle& t, auto&& visit) {
    const int lo = cellOf(t.box.min()[u_] - tolerance_, t.box.min()[v_] - tolerance_);
    const int hi = cellOf(t.box.max()[u_] + tolerance_, t.box.max()[v_] + tolerance_);
    for (int j = lo / cellsU_; j <= hi / cellsU_; ++j)
      for (int i = lo % cellsU_; i <= hi % cellsU_; ++i)
        visit(j * cellsU_ + i);
  };
  cellStart_.assign(std::size_t(cellsU_) * cellsV_ + 1, 0);
  for (const auto& t : triangles_)
    forCells(t, [&](int cell) { ++cellStart_[cell + 1]; });
  for (std::size_t c = 1; c < cellStart_.size(); ++c)
    cellStart_[c] += cellStart_[c - 1];
  cellTriangles_.resize(cellStart_.back());
  std::vector<int> filled(cellStart_.begin(), cellStart_.end() - 1);
  for (int t = 0; t < int(triangles_.size()); ++t)
    forCells(triangles_[t], [&](int cell) { cellTriangles_[filled[cell]++] = t; });
}

int EnclosureTest::cellOf(double u, double v) const {
  // Clamped alike for triangles and points, so a point inside a triangle's
  // grown box always lands in one of the triangle's cells.
  const int i = std::clamp(int(std::floor((u - bounds_.min()[u_]) / cellSize_)), 0, cellsU_ - 1);
  const int j = std::clamp(int(std::floor((v - bounds_.min()[v_]) / cellSize_)), 0, cellsV_ - 1);
  return j * cellsU_ + i;
}

EnclosureTest::Crossing EnclosureTest::crossing(const Triangle& t, const Vector3d& p) const {
  const double tol = tolerance_;
  if (p[u_] < t.box.min()[u_] - tol || p[u_] > t.box.max()[u_] + tol ||
      p[v_] < t.box.min()[v_] - tol || p[v_] > t.box.max()[v_] + tol ||
      t.box.max()[axis_] < p[axis_] - tol)
    return Crossing::None;  // the ray passes beside the triangle or starts beyond it
  // Twice the signed areas of (edge, point) in the projection: each is the
  // edge's projected length times the point's distance from its line.
  // Differences of doubles round to a relative error, so these signs are
  // right wherever the distances exceed the tolerance by far more than that.
  bool beyondLeft = false, beyondRight = false, nearLine = false;
  for (int k = 0; k < 3; ++k) {
    const Vector3d& a = t.corners[k];
    const Vector3d& b = t.corners[(k + 1) % 3];
    const Vector2d edge(b[u_] - a[u_], b[v_] - a[v_]);
    const Vector2d toPoint(p[u_] - a[u_], p[v_] - a[v_]);
    const double area = edge.x() * toPoint.y() - edge.y() * toPoint.x();
    // |area| <= tol |edge|, squared to spare the root.
    if (area * area <= tol * tol * edge.squaredNorm())
      nearLine = true;
    else if (area > 0)
      beyondLeft = true;
    else
      beyondRight = true;
  }
  if (beyondLeft && beyondRight) return Crossing::None;  // the projection misses the triangle
  if (nearLine) return Crossing::Doubtful;               // the ray grazes an edge or a vertex
  // The projection lies inside: the ray meets the plane at t = -side / n_axis.
  const double side = t.normal.dot(p - t.corners[0]);
  if (std::abs(side) <= tol * t.normal.norm()) return Crossing::Doubtful;  // p is on the triangle
  const bool facesAlongRay = beyondLeft;                   // n_axis has the sign of the areas
  if ((side > 0) == facesAlongRay) return Crossing::None;  // the plane is behind p
  return facesAlongRay ? Crossing::Exits : Crossing::Enters;
}

std::optional<int> EnclosureTest::crossingWindingNumber(const Vector3d& point) const {
  if (!bounds_.contains(point)) return 0;  // farther than the tolerance from every face
  const int cell = cellOf(point[u_], point[v_]);
  int winding = 0;
  for (int i = cellStart_[cell]; i < cellStart_[cell + 1]; ++i) {
    // An outward face the ray leaves through counts +1, one it enters -1.
    switch (crossing(triangles_[cellTriangles_[i]], point)) {
      case Crossing::None:
        break;
      case Crossing::Exits:
        ++winding;
        break;
      case Crossing::Enters:
        --winding;
        break;
      case Crossing::Doubtful:
        return std::nullopt;
    }
  }
  return winding;
}

bool EnclosureTest::encloses(const Vector3d& point) const {
  if (const auto winding = crossingWindingNumber(point)) return *winding >= 1;
  return windingNumber(mesh_, point) >= 0.5;
}

std::size_t countSelfIntersections(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<Vector3d, 3>> corners;
  std::vector<Eigen::AlignedBox3d> boxes;
  Eigen::AlignedBox3d bounds;
  for (auto f : mesh.faces()) {
    std::array<int, 3> ids;
    std::array<Vector3d, 3> points;
    Eigen::AlignedBox3d box;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      ids[k] = v.idx();
      points[k] = toEigen(mesh.point(v));
      box.extend(points[k++]);
    }
    faces.push_back(ids);
    corners.push_back(points);
    boxes.push_back(box);
    bounds.extend(box);
  }
  auto intersect = [&](int i, int j) {
    // Faces sharing a vertex meet there by construction; they are skipped.
    for (int a : faces[i])
      for (int b : faces[j])
        if (a == b) return false;
    const auto& s = corners[i];
    const auto& t = corners[j];
    for (int k = 0; k < 3; ++k)
      if (segmentHitsTriangle(s[k], s[(k + 1) % 3], t[0], t[1], t[2]) ||
          segmentHitsTriangle(t[k], t[(k + 1) % 3], s[0], s[1], s[2]))
        return true;
    return false;
  };
  // Sweep and prune along the longest side of the box: in order of their
  // boxes' low ends, a face meets only the following faces that start
  // before its box ends.
  if (faces.empty()) return 0;
  int axis = 0;
  bounds.sizes().maxCoeff(&axis);
  std::vector<int> order(faces.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    return std::pair(boxes[i].min()[axis], i) < std::pair(boxes[j].min()[axis], j);
  });
  std::size_t count = 0;
  for (std::size_t a = 0; a < order.size(); ++a) {
    const int i = order[a];
    for (std::size_t b = a + 1; b < order.size(); ++b) {
      const int j = order[b];
      if (boxes[j].min()[axis] > boxes[i].max()[axis]) break;
      if (boxes[i].intersects(boxes[j]) && intersect(i, j)) ++count;
    }
  }
  return count;
}

CageBuildResult buildCage(const Parameterization& param, const CageBuildOptions& options) {
  if (!param.canvas || param.uv.empty() || param.uv.size() != param.canvas->surface.n_vertices() ||
      param.normal.size() != param.uv.size())
    throw CageBuildError("the parameterization does not match its canvas");
  for (std::size_t v = 0; v < param.uv.size(); ++v)
    if (!param.uv[v].allFinite() || !param.normal[v].allFinite())
      throw CageBuildError("the parameterization has a non-finite value at vertex " +
                           std::to_string(v));
  if (options.resolution < 2) throw CageBuildError("resolution must be at least 2");

  const Grid grid = gridAround(param.uv, options.resolution);
  const Domain domain = triangulate(grid, coveredCells(grid, param.uv));
  const CanvasSamples samples = sampleCanvas(grid, param);
  const std::vector<Column> column = columns(grid, domain, param, samples);
  const double extent = grid.step * options.resolution;

  // The column each canvas vertex was projected onto: every canvas vertex
  // lies in a covered cell, whose corners are all domain vertices.
  std::vector<int> columnAt(grid.vertexCount(), -1);
  for (int d = 0; d < int(domain.gridIndex.size()); ++d)
    columnAt[grid.vertexIndex(domain.gridIndex[d].first, domain.gridIndex[d].second)] = d;

  CageBuildResult result;
  result.margin = options.margin * extent;
  double weight = options.constraintWeight;
  // Smoothing pulls the shell inward; where it uncovers canvas vertices, only
  // the columns there (and their neighbours) are pushed out further, so the
  // rest of the cage keeps its smoothness.
  std::vector<double> raise(column.size(), 0.0), lower(column.size(), 0.0);
  std::optional<ShellSmoother> smoother;
  for (int attempt = 1; attempt <= options.attempts; ++attempt) {
    if (options.cancelled && options.cancelled()) throw CageBuildError("cancelled");
    std::vector<int> top, bottom;
    TriMesh mesh = shellMesh(domain, column, result.margin, raise, lower, top, bottom);
    if (!smoother) smoother.emplace(mesh);
    smoother->smooth(mesh, weight);
    orientOutward(mesh);
    std::vector<int> outside;
    const EnclosureTest enclosure(mesh);
    for (std::size_t v = 0; v < samples.positions.size(); ++v)
      if (!enclosure.encloses(samples.positions[v])) outside.push_back(int(v));
    result.attempts = attempt;
    const bool intersects = countSelfIntersections(mesh) > 0;
    if (outside.empty() && !intersects) {
      result.cage.mesh = std::move(mesh);
      result.cage.domain = domain.positions;
      result.cage.domainTriangles = domain.triangles;
      result.cage.top = std::move(top);
      result.cage.bottom = std::move(bottom);
      for (const auto& c : column) {
        Frame frame;
        frame.point = c.point;
        frame.normal = c.normal;
        const Vector3d u = c.tangents.col(0) - c.tangents.col(0).dot(c.normal) * c.normal;
        frame.uAxis = u.norm() > 0 ? u.normalized() : param.origin.uAxis;
        frame.vAxis = frame.normal.cross(frame.uAxis);
        result.cage.frames.push_back(frame);
      }
      return result;
    }
    for (int v : outside) {
      const int d = columnAt[samples.gridVertex[v]];
      const Column& c = column[d];
      const double t = (samples.positions[v] - c.point).dot(c.normal);
      auto& side = t >= 0.5 * (c.low + c.high) ? raise : lower;
      side[d] = std::max(side[d], 0.0) + result.margin;
      for (int n : domain.neighbours[d])
        side[n] += 0.5 * result.margin;
    }
    // Folds are smoothed away by giving the Laplacian more say.
    if (intersects) weight *= 0.7;
  }
  throw CageBuildError("no cage enclosing the canvas without self-intersections after " +
                       std::to_string(options.attempts) +
                       " attempts; try another resolution or a larger margin");
}

}  // namespace geobrush
