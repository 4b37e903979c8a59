#include "cage_build.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>

namespace geobrush {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

Vector3d toEigen(const OpenMesh::Vec3d& p) {
  return {p[0], p[1], p[2]};
}

// A uniform grid over the parameter domain; C is made of some of its cells.
struct Grid {
  Vector2d corner;  // position of grid vertex (0, 0)
  double step = 1;
  int cellsX = 0;
  int cellsY = 0;

  int cellIndex(int i, int j) const { return j * cellsX + i; }
  int vertexIndex(int i, int j) const { return j * (cellsX + 1) + i; }
  Vector2d vertex(int i, int j) const { return corner + step * Vector2d(i, j); }
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

// Fits p ~ point + tangents (w - u) to the canvas vertices around u (its
// Voronoi cell, for a uniform grid the square of side `step` around u, and
// the eight cells beside it, so that sparse canvases still give a plane),
// then takes the extremal projections of the cell's own vertices.
void fitColumn(Column& column, const Vector2d& u, const std::vector<int>& around,
               const std::vector<int>& own, const Parameterization& param) {
  const TriMesh& surface = param.canvas->surface;
  Eigen::Matrix3d normalMatrix = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();
  for (int v : around) {
    const Vector2d w = param.uv[v] - u;
    const Vector3d basis(1, w.x(), w.y());
    normalMatrix += basis * basis.transpose();
    rhs += basis * toEigen(surface.point(TriMesh::VertexHandle(v))).transpose();
  }
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
  Vector3d normalSum = Vector3d::Zero();
  for (int v : own)
    normalSum += param.normal[v];
  column.normal = normalSum.normalized();
  column.low = std::numeric_limits<double>::infinity();
  column.high = -column.low;
  for (int v : own) {
    const double t =
        (toEigen(surface.point(TriMesh::VertexHandle(v))) - column.point).dot(column.normal);
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
std::vector<Column> columns(const Grid& grid, const Domain& domain, const Parameterization& param) {
  std::map<std::pair<int, int>, std::vector<int>> cellMembers;
  for (int v = 0; v < int(param.uv.size()); ++v) {
    const Vector2d local = (param.uv[v] - grid.corner) / grid.step;
    cellMembers[{int(std::lround(local.x())), int(std::lround(local.y()))}].push_back(v);
  }
  std::vector<Column> result(domain.positions.size());
  std::vector<std::uint8_t> placed(result.size(), 0);
  for (std::size_t d = 0; d < result.size(); ++d) {
    auto it = cellMembers.find(domain.gridIndex[d]);
    if (it == cellMembers.end()) continue;
    std::vector<int> around;
    const auto [i, j] = domain.gridIndex[d];
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        if (auto cell = cellMembers.find({i + di, j + dj}); cell != cellMembers.end())
          around.insert(around.end(), cell->second.begin(), cell->second.end());
    fitColumn(result[d], domain.positions[d], around, it->second, param);
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
    top[d] = mesh.add_vertex({up.x(), up.y(), up.z()}).idx();
    bottom[d] = mesh.add_vertex({down.x(), down.y(), down.z()}).idx();
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
// uniform graph Laplacian, solved once for x, y and z.
void optimize(TriMesh& mesh, double weight) {
  const int n = int(mesh.n_vertices());
  std::vector<Eigen::Triplet<double>> entries;
  for (auto v : mesh.vertices()) {
    const double valence = double(mesh.valence(v));
    entries.emplace_back(v.idx(), v.idx(), 1.0);
    for (auto w : mesh.vv_range(v))
      entries.emplace_back(v.idx(), w.idx(), -1.0 / valence);
  }
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseMatrix<double> identity(n, n);
  identity.setIdentity();
  const Eigen::SparseMatrix<double> system =
      Eigen::SparseMatrix<double>(laplacian.transpose() * laplacian) + weight * weight * identity;
  Eigen::MatrixX3d anchors(n, 3);
  for (auto v : mesh.vertices())
    anchors.row(v.idx()) = toEigen(mesh.point(v)).transpose();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
  if (solver.info() != Eigen::Success)
    throw CageBuildError("the cage smoothing system is singular");
  const Eigen::MatrixX3d smoothed = solver.solve(weight * weight * anchors);
  for (auto v : mesh.vertices()) {
    const auto row = smoothed.row(v.idx());
    mesh.point(v) = {row.x(), row.y(), row.z()};
  }
}

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

std::size_t countSelfIntersections(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> faces;
  std::vector<std::array<Vector3d, 3>> corners;
  std::vector<Eigen::AlignedBox3d> boxes;
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
  }
  std::size_t count = 0;
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (std::size_t j = i + 1; j < faces.size(); ++j) {
      if (!boxes[i].intersects(boxes[j])) continue;
      // Faces sharing a vertex meet there by construction; they are skipped.
      bool shared = false;
      for (int a : faces[i])
        for (int b : faces[j])
          shared |= a == b;
      if (shared) continue;
      const auto& s = corners[i];
      const auto& t = corners[j];
      bool hit = false;
      for (int k = 0; k < 3 && !hit; ++k) {
        hit |= segmentHitsTriangle(s[k], s[(k + 1) % 3], t[0], t[1], t[2]);
        hit |= segmentHitsTriangle(t[k], t[(k + 1) % 3], s[0], s[1], s[2]);
      }
      count += hit;
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
  const std::vector<Column> column = columns(grid, domain, param);
  const double extent = grid.step * options.resolution;
  const TriMesh& surface = param.canvas->surface;

  // The column each canvas vertex was projected onto.
  std::map<std::pair<int, int>, int> columnAt;
  for (int d = 0; d < int(domain.gridIndex.size()); ++d)
    columnAt[domain.gridIndex[d]] = d;
  std::vector<int> columnOf(surface.n_vertices());
  for (std::size_t v = 0; v < columnOf.size(); ++v) {
    const Vector2d local = (param.uv[v] - grid.corner) / grid.step;
    columnOf[v] = columnAt.at({int(std::lround(local.x())), int(std::lround(local.y()))});
  }

  CageBuildResult result;
  result.margin = options.margin * extent;
  double weight = options.constraintWeight;
  // Smoothing pulls the shell inward; where it uncovers canvas vertices, only
  // the columns there (and their neighbours) are pushed out further, so the
  // rest of the cage keeps its smoothness.
  std::vector<double> raise(column.size(), 0.0), lower(column.size(), 0.0);
  for (int attempt = 1; attempt <= options.attempts; ++attempt) {
    if (options.cancelled && options.cancelled()) throw CageBuildError("cancelled");
    std::vector<int> top, bottom;
    TriMesh mesh = shellMesh(domain, column, result.margin, raise, lower, top, bottom);
    optimize(mesh, weight);
    // The frames decide the handedness of (u, v, n); make the shell outward.
    if (signedVolume(mesh) < 0) {
      TriMesh flipped;
      for (auto v : mesh.vertices())
        flipped.add_vertex(mesh.point(v));
      for (auto f : mesh.faces()) {
        std::vector<TriMesh::VertexHandle> ids(mesh.fv_begin(f), mesh.fv_end(f));
        flipped.add_face(ids[0], ids[2], ids[1]);
      }
      mesh = std::move(flipped);
    }
    std::vector<int> outside;
    for (auto v : surface.vertices())
      if (windingNumber(mesh, toEigen(surface.point(v))) < 0.5) outside.push_back(v.idx());
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
      const int d = columnOf[v];
      const Column& c = column[d];
      const double t = (toEigen(surface.point(TriMesh::VertexHandle(v))) - c.point).dot(c.normal);
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
