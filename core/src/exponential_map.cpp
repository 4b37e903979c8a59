#include "geobrush/exponential_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <utility>

namespace geobrush {
namespace {

Eigen::Vector3d toEigen(const TriMesh::Point& p) {
  return {p[0], p[1], p[2]};
}

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

struct Lexicographic {
  bool operator()(const std::pair<double, int>& a, const std::pair<double, int>& b) const {
    return a > b;
  }
};

std::vector<std::vector<int>> meshAdjacency(const TriMesh& mesh) {
  std::vector<std::vector<int>> adjacency(mesh.n_vertices());
  for (auto v : mesh.vertices())
    for (auto w : mesh.vv_range(v))
      adjacency[v.idx()].push_back(w.idx());
  return adjacency;
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

std::vector<Eigen::Vector3d> surfaceNormals(const Canvas& canvas) {
  const bool fromSource = canvas.source != nullptr;
  const TriMesh& mesh = fromSource ? canvas.source->surface : canvas.surface;
  std::vector<Eigen::Vector3d> normals(canvas.surface.n_vertices());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const int v = fromSource ? canvas.sourceVertex[i] : static_cast<int>(i);
    const Eigen::Vector3d n = angleWeightedNormal(mesh, TriMesh::VertexHandle(v));
    if (!(n.norm() > 0)) {
      throw DemError("canvas", "canvas vertex " + std::to_string(i) +
                                   " has no surface normal (its faces are degenerate or cancel "
                                   "out)");
    }
    normals[i] = n.normalized();
  }
  return normals;
}

std::vector<Eigen::Vector3d> interpolatedNormals(const Canvas& canvas,
                                                 const std::vector<Eigen::Vector3d>& surface,
                                                 double epsilon) {
  const std::vector<Eigen::Vector3d> p = points(canvas.surface);
  const double diagonal = boundingDiagonal(p);
  const double eps = epsilon * diagonal * diagonal;
  std::vector<char> onBoundary(p.size(), 0);
  for (int b : canvas.boundary)
    onBoundary[b] = 1;
  std::vector<Eigen::Vector3d> normals = surface;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (onBoundary[i]) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weights = 0;
    for (int b : canvas.boundary) {
      const double w = 1 / ((p[b] - p[i]).squaredNorm() + eps);
      sum += w * surface[b];
      weights += w;
    }
    if (!(sum.norm() > 1e-9 * weights)) {
      throw DemError("canvas", "the canvas boundary's normals cancel out at canvas vertex " +
                                   std::to_string(i) +
                                   ": the canvas wraps too far around the surface for Eq. 1; "
                                   "paint a flatter canvas or use the original DEM");
    }
    normals[i] = sum.normalized();
  }
  return normals;
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

std::vector<std::vector<int>> nearestNeighbours(const std::vector<Eigen::Vector3d>& p, int k) {
  const std::size_t n = p.size();
  std::vector<std::vector<int>> result(n);
  if (n < 2 || k < 1) return result;
  const std::size_t want = std::min<std::size_t>(static_cast<std::size_t>(k), n - 1);
  Eigen::Vector3d lo = p.front(), hi = p.front();
  for (const auto& x : p) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  // About a few points per cell for points spread over a surface.
  const double diagonal = (hi - lo).norm();
  const double h = diagonal > 0 ? 2 * diagonal / std::sqrt(static_cast<double>(n)) : 1.0;
  const Eigen::Array3i dims = (((hi - lo) / h).array().floor().cast<int>() + 1).matrix();
  auto cellOf = [&](const Eigen::Vector3d& x) -> Eigen::Array3i {
    return (((x - lo) / h).array().floor().cast<int>()).min(dims - 1).max(0);
  };
  auto key = [&](const Eigen::Array3i& c) {
    return (static_cast<std::int64_t>(c.x()) * dims.y() + c.y()) * dims.z() + c.z();
  };
  std::unordered_map<std::int64_t, std::vector<int>> cells;
  for (std::size_t i = 0; i < n; ++i)
    cells[key(cellOf(p[i]))].push_back(static_cast<int>(i));

  const int maxRing = dims.maxCoeff();
  std::vector<std::pair<double, int>> best;
  for (std::size_t i = 0; i < n; ++i) {
    best.clear();
    const Eigen::Array3i home = cellOf(p[i]);
    auto consider = [&](int j) {
      if (j == static_cast<int>(i)) return;
      const std::pair<double, int> candidate{(p[j] - p[i]).squaredNorm(), j};
      if (best.size() == want && !(candidate < best.back())) return;
      best.insert(std::upper_bound(best.begin(), best.end(), candidate), candidate);
      if (best.size() > want) best.pop_back();
    };
    for (int r = 0; r <= maxRing; ++r) {
      for (int x = home.x() - r; x <= home.x() + r; ++x) {
        for (int y = home.y() - r; y <= home.y() + r; ++y) {
          for (int z = home.z() - r; z <= home.z() + r; ++z) {
            const Eigen::Array3i c(x, y, z);
            if ((c - home).abs().maxCoeff() != r || (c < 0).any() || (c >= dims).any()) continue;
            const auto it = cells.find(key(c));
            if (it == cells.end()) continue;
            for (int j : it->second)
              consider(j);
          }
        }
      }
      // Points in ring r + 1 or beyond are at least r * h away.
      if (best.size() == want && best.back().first <= (r * h) * (r * h)) break;
    }
    for (const auto& [d, j] : best)
      result[i].push_back(j);
  }
  return result;
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
    queue_.push_back({distance_[s], v});
    std::push_heap(queue_.begin(), queue_.end(), Lexicographic());
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
  return slot_[vertex];
}

int ExponentialMapGrowth::fixNext() {
  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end(), Lexicographic());
    const auto [d, v] = queue_.back();
    queue_.pop_back();
    const int i = slot_[v];
    if (fixed_[i] || d > distance_[i]) continue;
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
        queue_.push_back({through, w});
        std::push_heap(queue_.begin(), queue_.end(), Lexicographic());
      }
    }
    return v;
  }
  return -1;
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
  const std::vector<Eigen::Vector3d> p = points(canvas.surface);
  const std::size_t n = p.size();
  std::vector<int> originCorners;
  for (auto v : canvas.surface.fv_range(TriMesh::FaceHandle(canvas.originFace)))
    originCorners.push_back(v.idx());
  ExponentialMapGrowth::Graph graph;
  graph.vertexCount = n;
  graph.point = [&](int v) { return p[v]; };
  graph.normal = [&](int v) { return normals[v]; };
  graph.neighbours = [&](int v, std::vector<int>& out) {
    out.insert(out.end(), adjacency[v].begin(), adjacency[v].end());
  };
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

std::vector<std::uint8_t> reversedFaces(const TriMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        double threshold) {
  std::vector<std::uint8_t> flags(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> c;
    Eigen::Vector3d dem = Eigen::Vector3d::Zero();
    int i = 0;
    for (auto v : mesh.fv_range(f)) {
      c[i++] = toEigen(mesh.point(v));
      dem += normals[v.idx()];
    }
    Eigen::Vector3d face = (c[1] - c[0]).cross(c[2] - c[0]);
    const double dot =
        face.norm() > 0 && dem.norm() > 0 ? face.normalized().dot(dem.normalized()) : 0.0;
    flags[f.idx()] = dot < threshold;
  }
  return flags;
}

std::vector<std::uint8_t> growFaceRing(const TriMesh& mesh, std::vector<std::uint8_t> flags,
                                       int rings) {
  std::vector<char> marked(mesh.n_vertices());
  for (int r = 0; r < rings; ++r) {
    std::fill(marked.begin(), marked.end(), 0);
    for (auto f : mesh.faces())
      if (flags[f.idx()])
        for (auto v : mesh.fv_range(f))
          marked[v.idx()] = 1;
    for (auto f : mesh.faces())
      for (auto v : mesh.fv_range(f))
        if (marked[v.idx()]) flags[f.idx()] = 1;
  }
  return flags;
}

DemResult discreteExponentialMap(const Canvas& canvas, const DemOptions& options) {
  checkOptions(options);
  checkCanvas(canvas);
  DemResult result;
  const std::vector<Eigen::Vector3d> surface = surfaceNormals(canvas);
  result.normal =
      options.generalized ? interpolatedNormals(canvas, surface, options.epsilon) : surface;
  result.origin = originFrame(canvas, result.normal, options.angleDegrees);

  std::vector<std::vector<int>> adjacency = meshAdjacency(canvas.surface);
  if (options.generalized) {
    // Section 4.2 propagates over k nearest neighbours; the mesh edges stay in so that every
    // vertex is reached even where the k-nearest-neighbour graph falls apart into clusters.
    const auto knn = nearestNeighbours(points(canvas.surface), options.neighbours);
    for (std::size_t i = 0; i < knn.size(); ++i) {
      for (int j : knn[i]) {
        adjacency[i].push_back(j);
        adjacency[j].push_back(static_cast<int>(i));
      }
    }
  }
  for (auto& list : adjacency) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  result.uv = propagate(canvas, result.normal, result.origin, adjacency, !options.generalized);
  for (std::size_t i = 0; i < result.uv.size(); ++i) {
    if (!result.uv[i].allFinite()) {
      throw DemError("canvas", "the map of canvas vertex " + std::to_string(i) +
                                   " is not finite (coincident vertices?)");
    }
  }
  result.reversedFaces = growFaceRing(
      canvas.surface, reversedFaces(canvas.surface, result.normal, options.reversedThreshold),
      options.reversedRing);
  return result;
}

}  // namespace geobrush
