#include "rbf_warp.hpp"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "geobrush/border_loop.hpp"
#include "geobrush/submesh.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {
namespace {

// Shortest edge paths on a mesh, reusing its arrays between searches (a loop's segments are short
// on a large template).
class EdgePaths {
 public:
  explicit EdgePaths(const TriMesh& mesh)
      : mesh_(mesh),
        distance_(mesh.n_vertices(), kUnreached),
        via_(mesh.n_vertices(), TriMesh::HalfedgeHandle()) {}

  // The halfedges of a shortest path from `from` to `to`, in order; empty where none exists.
  std::vector<TriMesh::HalfedgeHandle> path(int from, int to) {
    reset();
    search(from, to);
    std::vector<TriMesh::HalfedgeHandle> halfedges;
    if (distance_[std::size_t(to)] == kUnreached) return halfedges;
    for (int v = to; v != from;) {
      halfedges.push_back(via_[std::size_t(v)]);
      v = mesh_.from_vertex_handle(halfedges.back()).idx();
    }
    std::reverse(halfedges.begin(), halfedges.end());
    return halfedges;
  }

 private:
  // Dijkstra from `from` until `to` is settled; equal distances pop in vertex order.
  void search(int from, int to) {
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    settle(from, 0.0, TriMesh::HalfedgeHandle());
    queue.emplace(0.0, from);
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (v == to) return;
      if (d > distance_[std::size_t(v)]) continue;
      for (auto h : mesh_.voh_range(TriMesh::VertexHandle(v))) {
        const int w = mesh_.to_vertex_handle(h).idx();
        const double through = d + mesh_.calc_edge_length(h);
        if (through >= distance_[std::size_t(w)]) continue;
        settle(w, through, h);
        queue.emplace(through, w);
      }
    }
  }

  void settle(int v, double d, TriMesh::HalfedgeHandle h) {
    if (distance_[std::size_t(v)] == kUnreached) touched_.push_back(v);
    distance_[std::size_t(v)] = d;
    via_[std::size_t(v)] = h;
  }

  void reset() {
    for (int v : touched_)
      distance_[std::size_t(v)] = kUnreached;
    touched_.clear();
  }

  const TriMesh& mesh_;
  std::vector<double> distance_;
  std::vector<TriMesh::HalfedgeHandle> via_;
  std::vector<int> touched_;
};

// The pairs at L's corners: pair order with consecutive pairs on one template vertex merged (the
// first kept) and the closing repeats dropped.
std::vector<int> loopCorners(const PointPairs& pairs) {
  const auto& t = pairs.templateVertex;
  std::vector<int> corners;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (corners.empty() || t[std::size_t(corners.back())] != t[i]) corners.push_back(int(i));
  while (corners.size() > 1 && t[std::size_t(corners.back())] == t[std::size_t(corners.front())])
    corners.pop_back();
  return corners;
}

// The t_b_i at L's corners, in order.
std::vector<int> pairLoop(const PointPairs& pairs) {
  std::vector<int> loop;
  for (int i : loopCorners(pairs))
    loop.push_back(pairs.templateVertex[std::size_t(i)]);
  return loop;
}

// The boundary's shifts carried over the patch (Dirichlet problem of the uniform graph
// Laplacian), so the rings next to the boundary follow it rather than fold against it.
void extendShifts(TriMesh& patch, std::vector<Eigen::Vector3d>& shift) {
  std::vector<int> unknown(patch.n_vertices(), -1);
  int count = 0;
  for (const auto v : patch.vertices())
    if (!patch.is_boundary(v)) unknown[std::size_t(v.idx())] = count++;
  if (count > 0) {
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(count, 3);
    for (const auto v : patch.vertices()) {
      const int row = unknown[std::size_t(v.idx())];
      if (row < 0) continue;
      for (const auto w : patch.vv_range(v)) {
        entries.emplace_back(row, row, 1.0);
        const int column = unknown[std::size_t(w.idx())];
        if (column >= 0)
          entries.emplace_back(row, column, -1.0);
        else
          rhs.row(row) += shift[std::size_t(w.idx())].transpose();
      }
    }
    Eigen::SparseMatrix<double> laplacian(count, count);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
    const Eigen::MatrixX3d solved = solver.solve(rhs);
    for (const auto v : patch.vertices())
      if (const int row = unknown[std::size_t(v.idx())]; row >= 0)
        shift[std::size_t(v.idx())] = solved.row(row).transpose();
  }
  for (const auto v : patch.vertices())
    patch.set_point(v, toPoint(pointOf(patch, v) + shift[std::size_t(v.idx())]));
}

// The border polyline from pair `first`'s point to pair `last`'s through the pairs between (those
// whose template vertex merged into a corner of L included), by arc length.
class BorderStretch {
 public:
  BorderStretch(const PointPairs& pairs, int first, int last) {
    const auto n = int(pairs.border.size());
    for (int i = first;; i = (i + 1) % n) {
      points_.push_back(pairs.border[std::size_t(i)]);
      if (i == last) break;
    }
    lengths_.push_back(0);
    for (std::size_t i = 1; i < points_.size(); ++i)
      lengths_.push_back(lengths_.back() + (points_[i] - points_[i - 1]).norm());
  }
  // The point at fraction s of the stretch's length.
  Eigen::Vector3d at(double s) const {
    const double target = s * lengths_.back();
    std::size_t i = 1;
    while (i + 1 < points_.size() && lengths_[i] < target)
      ++i;
    if (i >= points_.size()) return points_.front();
    const double piece = lengths_[i] - lengths_[i - 1];
    const double t = piece > 0 ? std::clamp((target - lengths_[i - 1]) / piece, 0.0, 1.0) : 0.0;
    return points_[i - 1] + t * (points_[i] - points_[i - 1]);
  }
  // The points strictly between the ends (the border points of pairs merged into a corner) and
  // their fractions of the stretch's length.
  std::size_t innerCount() const { return points_.size() - 2; }
  const Eigen::Vector3d& inner(std::size_t i) const { return points_[i + 1]; }
  double innerFraction(std::size_t i) const {
    return lengths_.back() > 0 ? lengths_[i + 1] / lengths_.back() : 0.0;
  }

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> lengths_;
};

// Order-preserving matching [ours]: index pairs (i, j), both increasing, that match every element
// of the shorter of `a` and `b` to one of the longer with the least total |a_i - b_j| (dynamic
// programming over prefixes).
std::vector<std::pair<std::size_t, std::size_t>> monotoneMatch(const std::vector<double>& a,
                                                               const std::vector<double>& b) {
  if (a.size() > b.size()) {
    auto swapped = monotoneMatch(b, a);
    for (auto& [i, j] : swapped)
      std::swap(i, j);
    return swapped;
  }
  const std::size_t n = a.size(), m = b.size();
  const double unreachable = std::numeric_limits<double>::infinity();
  // cost[i][j]: a's first i matched into b's first j.
  std::vector<std::vector<double>> cost(n + 1, std::vector<double>(m + 1, unreachable));
  std::fill(cost[0].begin(), cost[0].end(), 0.0);
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = i; j <= m; ++j)
      cost[i][j] = std::min(cost[i][j - 1], cost[i - 1][j - 1] + std::abs(a[i - 1] - b[j - 1]));
  std::vector<std::pair<std::size_t, std::size_t>> matched;
  for (std::size_t i = n, j = m; i > 0; --j) {
    if (cost[i][j] == cost[i - 1][j - 1] + std::abs(a[i - 1] - b[j - 1])) {
      matched.emplace_back(i - 1, j - 1);
      --i;
    }
  }
  std::reverse(matched.begin(), matched.end());
  return matched;
}

// Fraction s of a path mapped through the anchors (path fraction, stretch fraction), both
// increasing, and the ends (0, 0) and (1, 1), piecewise linearly.
double throughAnchors(double s, const std::vector<std::pair<double, double>>& anchors) {
  std::pair<double, double> from{0.0, 0.0}, to{1.0, 1.0};
  for (const auto& anchor : anchors) {
    if (anchor.first <= s) from = anchor;
    if (anchor.first > s) {
      to = anchor;
      break;
    }
  }
  const double width = to.first - from.first;
  return width > 0 ? from.second + (s - from.first) / width * (to.second - from.second)
                   : from.second;
}

// The cropped template's boundary vertex of a template vertex; invalid where the crop left it out
// or left it inside (a spur of the path).
TriMesh::VertexHandle croppedBoundaryVertex(const RbfWarpResult& result, int templateVertex) {
  const auto& kept = result.sourceVertex;
  const auto at = std::lower_bound(kept.begin(), kept.end(), templateVertex);
  if (at == kept.end() || *at != templateVertex) return TriMesh::VertexHandle();
  const TriMesh::VertexHandle v(int(at - kept.begin()));
  return result.mesh.is_boundary(v) ? v : TriMesh::VertexHandle();
}

// Where the crop's boundary is pinned to the border: the boundary loop that holds the most corners
// t_b_i, turned to run in pair order, and its corners as (position on the loop, pair index), each
// further along the loop than the one before, within one turn.
struct SnapAnchors {
  std::vector<int> loop;
  std::vector<std::pair<std::size_t, int>> pinned;
};

// The corners on `loop` in pair order, those that would step backwards or past a turn left out.
std::vector<std::pair<std::size_t, int>> pinnedCorners(const RbfWarpResult& result,
                                                       const PointPairs& pairs,
                                                       const std::vector<int>& loop) {
  std::vector<int> position(result.mesh.n_vertices(), -1);
  for (std::size_t i = 0; i < loop.size(); ++i)
    position[std::size_t(loop[i])] = int(i);
  std::vector<std::pair<std::size_t, int>> pinned;
  std::size_t travelled = 0;
  for (int corner : loopCorners(pairs)) {
    const auto v = croppedBoundaryVertex(result, pairs.templateVertex[std::size_t(corner)]);
    if (!v.is_valid() || position[std::size_t(v.idx())] < 0) continue;
    const auto at = std::size_t(position[std::size_t(v.idx())]);
    const std::size_t step =
        pinned.empty() ? 0 : (at + loop.size() - pinned.back().first) % loop.size();
    if (!pinned.empty() && (step == 0 || travelled + step >= loop.size())) continue;
    travelled += step;
    pinned.emplace_back(at, corner);
  }
  return pinned;
}

SnapAnchors snapAnchors(const RbfWarpResult& result, const PointPairs& pairs) {
  SnapAnchors best;
  for (auto loop : boundaryLoops(result.mesh))
    for (int turn = 0; turn < 2; ++turn) {
      if (turn == 1) std::reverse(loop.begin(), loop.end());
      auto pinned = pinnedCorners(result, pairs, loop);
      if (pinned.size() > best.pinned.size()) best = {loop, std::move(pinned)};
    }
  return best;
}

// Ears [ours]: a boundary vertex with one face, snapped between its two neighbours where the border
// runs straight, would make that face flat against the holed mesh's; the face is left out (its
// neighbours' edge becomes the boundary). Flat: within this fraction of the neighbours' distance
// of the line through them.
constexpr double kFlatEar = 1e-3;

void dropFlatEars(RbfWarpResult& result, std::vector<Eigen::Vector3d>& shift) {
  const TriMesh& mesh = result.mesh;
  const auto target = [&](TriMesh::VertexHandle v) {
    return Eigen::Vector3d(pointOf(mesh, v) + shift[std::size_t(v.idx())]);
  };
  std::vector<char> flat(mesh.n_faces(), 0);
  std::size_t dropped = 0;
  for (const auto v : mesh.vertices()) {
    if (!mesh.is_boundary(v) || mesh.valence(v) != 2) continue;
    const auto out = mesh.halfedge_handle(v);
    const Eigen::Vector3d a = target(mesh.to_vertex_handle(out));
    const Eigen::Vector3d b = target(mesh.from_vertex_handle(mesh.prev_halfedge_handle(out)));
    const double chord = (b - a).norm();
    if ((target(v) - a).cross(b - a).norm() > kFlatEar * chord * chord) continue;
    const auto face = mesh.face_handle(mesh.opposite_halfedge_handle(out));
    if (!flat[std::size_t(face.idx())]) ++dropped;
    flat[std::size_t(face.idx())] = 1;
  }
  if (dropped == 0 || dropped == mesh.n_faces()) return;
  std::vector<int> faces;
  for (const auto f : mesh.faces())
    if (!flat[std::size_t(f.idx())]) faces.push_back(f.idx());
  Submesh kept = extractSubmesh(mesh, faces);
  if (kept.unattachedFace >= 0) return;
  std::vector<Eigen::Vector3d> keptShift;
  std::vector<int> keptSource;
  for (int v : kept.sourceVertex) {
    keptShift.push_back(shift[std::size_t(v)]);
    keptSource.push_back(result.sourceVertex[std::size_t(v)]);
  }
  result.mesh = std::move(kept.surface);
  result.sourceVertex = std::move(keptSource);
  shift = std::move(keptShift);
}

// Snap [ours]: the cropped template's boundary laid onto the border polyline. Each pinned corner
// t_b_i goes to b_i. Between pinned corners t_b_i and t_b_j, the border points between b_i and b_j
// each take the boundary vertex nearest in fraction of length (monotoneMatch), so that the weld
// shares every border point rather than zipping a strip across a reflex one; the other boundary
// vertices go to the border polyline at their fraction of the boundary's length (measured on the
// template before the warp), mapped through those anchors. Flat ears are left out (dropFlatEars)
// and the rest of the patch follows the boundary's shifts (extendShifts).
void snapBoundary(const TriMesh& mesh, const PointPairs& pairs, RbfWarpResult& result) {
  const SnapAnchors anchors = snapAnchors(result, pairs);
  if (anchors.pinned.size() < 2) return;
  const auto& loop = anchors.loop;
  const auto templatePoint = [&](std::size_t position) {
    const int v = loop[position % loop.size()];
    return pointOf(mesh, TriMesh::VertexHandle(result.sourceVertex[std::size_t(v)]));
  };
  std::vector<Eigen::Vector3d> shift(result.mesh.n_vertices(), Eigen::Vector3d::Zero());
  const auto place = [&](std::size_t position, const Eigen::Vector3d& p) {
    const TriMesh::VertexHandle v(loop[position % loop.size()]);
    shift[std::size_t(v.idx())] = p - pointOf(result.mesh, v);
  };
  for (std::size_t k = 0; k < anchors.pinned.size(); ++k) {
    const auto [from, first] = anchors.pinned[k];
    const auto [to, last] = anchors.pinned[(k + 1) % anchors.pinned.size()];
    const std::size_t steps = (to + loop.size() - from) % loop.size();
    const BorderStretch stretch(pairs, first, last);
    place(from, pairs.border[std::size_t(first)]);
    std::vector<double> along{0.0}, borderFraction;
    for (std::size_t i = 1; i <= steps; ++i)
      along.push_back(along.back() +
                      (templatePoint(from + i) - templatePoint(from + i - 1)).norm());
    std::vector<double> innerFraction;
    for (std::size_t i = 1; i < steps; ++i)
      innerFraction.push_back(along.back() > 0 ? along[i] / along.back() : 0.0);
    for (std::size_t i = 0; i < stretch.innerCount(); ++i)
      borderFraction.push_back(stretch.innerFraction(i));
    std::vector<std::pair<double, double>> matched;
    std::vector<int> anchoredTo(innerFraction.size(), -1);
    for (const auto& [i, j] : monotoneMatch(innerFraction, borderFraction)) {
      matched.emplace_back(innerFraction[i], borderFraction[j]);
      anchoredTo[i] = int(j);
    }
    for (std::size_t i = 0; i < innerFraction.size(); ++i)
      place(from + 1 + i, anchoredTo[i] >= 0
                              ? stretch.inner(std::size_t(anchoredTo[i]))
                              : stretch.at(throughAnchors(innerFraction[i], matched)));
  }
  dropFlatEars(result, shift);
  extendShifts(result.mesh, shift);
}

TriMesh displaced(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& displacement) {
  TriMesh warped = mesh;
  for (auto v : warped.vertices())
    warped.set_point(v, toPoint(pointOf(mesh, v) + displacement[std::size_t(v.idx())]));
  return warped;
}

Eigen::Vector3d borderCentroid(const PointPairs& pairs) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& b : pairs.border)
    sum += b;
  return sum / double(pairs.border.size());
}

double borderRadius(const PointPairs& pairs) {
  const Eigen::Vector3d centre = borderCentroid(pairs);
  double sum = 0;
  for (const auto& b : pairs.border)
    sum += (b - centre).norm();
  return sum / double(pairs.border.size());
}

// Crop [ours]: the warped template's faces on the hole side of L, as a mesh of its own. L and the
// side are found on the aligned template before the warp, whose far parts a wide kernel can fold.
void crop(const TriMesh& mesh, const TriMesh& warped, const PointPairs& pairs,
          RbfWarpResult& result) {
  const std::vector<int> loop = pairLoop(pairs);
  if (loop.size() < 3)
    throw RbfWarpError("pairs",
                       "the pairs name fewer than 3 distinct template vertices in a row: "
                       "no line L to crop along");
  const std::vector<char> onL = pathEdges(mesh, loop);
  if (std::find(onL.begin(), onL.end(), 1) == onL.end())
    throw RbfWarpError("pairs",
                       "the line L through the paired template vertices does not separate the "
                       "template: its paths run there and back and enclose nothing");
  const int seed = nearestSurfacePoint(mesh, borderCentroid(pairs)).face;
  const Submesh kept = extractSubmesh(warped, floodFaces(mesh, onL, seed));
  if (kept.unattachedFace >= 0)
    throw RbfWarpError("pairs", "the cropped template touches itself at a corner of face " +
                                    std::to_string(kept.unattachedFace) +
                                    " (L passes a vertex twice): use fewer or other pairs");
  result.mesh = kept.surface;
  result.sourceVertex = kept.sourceVertex;
}

std::vector<int> identity(std::size_t n) {
  std::vector<int> index(n);
  for (std::size_t i = 0; i < n; ++i)
    index[i] = int(i);
  return index;
}

// Eqs. 4-6 on the chosen constraints: the displacement of every template vertex and cond(A).
void solveWarp(const TriMesh& mesh, const KnnGraph& graph, const PointPairs& pairs,
               const RbfWarpOptions& options, RbfWarpResult& result) {
  std::vector<int> constraint;
  std::vector<Eigen::Vector3d> translation;  // b_i - t_b_i, Eq. 6's right-hand side
  for (int i : result.constraintPair) {
    const int v = pairs.templateVertex[std::size_t(i)];
    constraint.push_back(v);
    translation.push_back(pairs.border[std::size_t(i)] - pointOf(mesh, v));
  }
  GeodesicRbfOptions rbf;
  rbf.kernel = options.kernel;
  rbf.tMax = result.tMax;
  rbf.reg = options.reg;
  const std::vector<Eigen::Vector3d> points =
      options.straightDistance ? vertexPoints(mesh) : std::vector<Eigen::Vector3d>{};
  rbf.straightPoints = points;
  GeodesicRbfResult solved;
  try {
    solved = geodesicRbf(graph, constraint, translation, rbf);
  } catch (const std::invalid_argument& e) {
    throw RbfWarpError("pairs", e.what());
  }
  result.conditionNumber = solved.conditionNumber;
  // Eq. 3 with alpha == 1 [ours, the spec's default]: d(x) = d_h(x), so the constraints hold
  // exactly (up to reg) wherever L is, and the whole template moves.
  result.displacement = std::move(solved.displacement);
}

double maxDistance(const std::vector<Eigen::Vector3d>& points, const PointPairs& pairs,
                   const std::vector<int>& which) {
  double worst = 0;
  for (int i : which)
    worst = std::max(worst, (points[std::size_t(pairs.templateVertex[std::size_t(i)])] -
                             pairs.border[std::size_t(i)])
                                .norm());
  return worst;
}

}  // namespace

void requireValidInputs(const TriMesh& mesh, const PointPairs& pairs) {
  if (mesh.n_faces() == 0) throw RbfWarpError("template", "the template has no faces");
  if (pairs.border.size() != pairs.templateVertex.size())
    throw RbfWarpError("pairs", std::to_string(pairs.border.size()) + " border points but " +
                                    std::to_string(pairs.templateVertex.size()) +
                                    " template vertices");
  for (std::size_t i = 0; i < pairs.border.size(); ++i) {
    const int v = pairs.templateVertex[i];
    if (v < 0 || v >= int(mesh.n_vertices()))
      throw RbfWarpError("pairs", "pair " + std::to_string(i) + " names template vertex " +
                                      std::to_string(v) + ", which the template (" +
                                      std::to_string(mesh.n_vertices()) + " vertices) lacks");
    if (!pairs.border[i].allFinite())
      throw RbfWarpError("pairs", "border point " + std::to_string(i) + " is not finite");
  }
}

std::vector<int> constraintPairs(const PointPairs& pairs, int stride, int& dropped) {
  std::vector<int> chosen;
  std::vector<int> taken = pairs.templateVertex;
  std::sort(taken.begin(), taken.end());
  taken.erase(std::unique(taken.begin(), taken.end()), taken.end());
  std::vector<char> used(taken.size(), 0);
  dropped = 0;
  for (std::size_t i = 0; i < pairs.templateVertex.size(); i += std::size_t(stride)) {
    const auto at = std::lower_bound(taken.begin(), taken.end(), pairs.templateVertex[i]);
    char& u = used[std::size_t(at - taken.begin())];
    if (u) {
      ++dropped;
      continue;
    }
    u = 1;
    chosen.push_back(int(i));
  }
  if (chosen.size() < 3)
    throw RbfWarpError("pairs",
                       "the warp needs at least 3 constraints on distinct template "
                       "vertices; stride " +
                           std::to_string(stride) + " leaves " + std::to_string(chosen.size()));
  return chosen;
}

std::vector<std::vector<TriMesh::HalfedgeHandle>> pathSegments(const TriMesh& mesh,
                                                               const std::vector<int>& loop) {
  std::vector<std::vector<TriMesh::HalfedgeHandle>> segments;
  EdgePaths paths(mesh);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int from = loop[i], to = loop[(i + 1) % loop.size()];
    segments.push_back(paths.path(from, to));
    if (segments.back().empty())
      throw RbfWarpError("pairs", "template vertices " + std::to_string(from) + " and " +
                                      std::to_string(to) +
                                      " (consecutive pairs) are not connected on the template");
  }
  return segments;
}

std::vector<char> pathEdges(const TriMesh& mesh, const std::vector<int>& loop) {
  // An edge two segments run along, there and back, is a spur of the path, not a border between
  // two sides: L is the edges the path takes an odd number of times.
  std::vector<char> onL(mesh.n_edges(), 0);
  for (const auto& segment : pathSegments(mesh, loop))
    for (const auto h : segment)
      onL[std::size_t(mesh.edge_handle(h).idx())] ^= 1;
  return onL;
}

std::vector<int> floodFaces(const TriMesh& mesh, const std::vector<char>& onL, int seed) {
  std::vector<char> reached(mesh.n_faces(), 0);
  std::vector<int> faces{seed};
  reached[std::size_t(seed)] = 1;
  for (std::size_t next = 0; next < faces.size(); ++next)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(faces[next]))) {
      if (onL[std::size_t(mesh.edge_handle(h).idx())]) continue;
      const auto g = mesh.opposite_face_handle(h);
      if (!g.is_valid() || reached[std::size_t(g.idx())]) continue;
      reached[std::size_t(g.idx())] = 1;
      faces.push_back(g.idx());
    }
  for (auto e : mesh.edges()) {
    if (!onL[std::size_t(e.idx())] || mesh.is_boundary(e)) continue;
    const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
    const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
    if (reached[std::size_t(f0.idx())] && reached[std::size_t(f1.idx())])
      throw RbfWarpError("pairs",
                         "the line L through the paired template vertices does not "
                         "separate the template: the flood from the face nearest the "
                         "border's centroid reaches both sides of its edge " +
                             std::to_string(e.idx()) +
                             " (pairs out of the border's order, or L not closed "
                             "around a part of the template?)");
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

RbfWarpResult rbfWarp(const TriMesh& mesh, const KnnGraph& graph, const PointPairs& pairs,
                      const RbfWarpOptions& options) {
  requireValidInputs(mesh, pairs);
  if (graph.size() != int(mesh.n_vertices()))
    throw std::invalid_argument("rbf warp: the kNN graph is not the template's");
  RbfWarpResult result;
  result.bboxDiagonal = boundingDiagonal(mesh);
  result.tMax = options.tMax > 0         ? options.tMax
                : options.tMaxFromBorder ? borderRadius(pairs)
                                         : result.bboxDiagonal;  // Eq. 5 [paper]
  if (!(result.tMax > 0))
    throw RbfWarpError("pairs", "the border points coincide: no width for the kernel");
  result.constraintPair = constraintPairs(pairs, options.stride, result.duplicatesDropped);
  solveWarp(mesh, graph, pairs, options, result);

  const TriMesh warped = displaced(mesh, result.displacement);
  const auto points = vertexPoints(warped);
  const double diagonal = result.bboxDiagonal > 0 ? result.bboxDiagonal : 1.0;
  result.maxResidual = maxDistance(points, pairs, result.constraintPair) / diagonal;
  result.maxResidualAllPairs = maxDistance(points, pairs, identity(pairs.border.size())) / diagonal;

  if (options.crop) {
    crop(mesh, warped, pairs, result);
    if (options.snapBoundary) snapBoundary(mesh, pairs, result);
  } else {
    result.mesh = warped;
    result.sourceVertex = identity(mesh.n_vertices());
  }
  for (int i : result.constraintPair)
    result.constraintsKept +=
        int(std::binary_search(result.sourceVertex.begin(), result.sourceVertex.end(),
                               pairs.templateVertex[std::size_t(i)]));
  return result;
}

}  // namespace geobrush
