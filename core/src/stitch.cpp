#include "geobrush/stitch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <future>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>
#include <optional>
#include <queue>
#include <unordered_set>
#include <utility>

#include <Eigen/Geometry>

#include "append_faces.hpp"
#include "background_work.hpp"

#include "geobrush/domain_locator.hpp"
#include "geobrush/face_selection.hpp"
#include "geobrush/loop_zip.hpp"
#include "geobrush/node.hpp"
#include "geobrush/parallel.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;

// Mean distance from the points of `a` to the nearest point of `b`.
double meanNearestDistance(const std::vector<Vector2d>& a, const std::vector<Vector2d>& b) {
  double sum = 0;
  for (const auto& p : a) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& q : b)
      best = std::min(best, (p - q).squaredNorm());
    sum += std::sqrt(best);
  }
  return sum / double(a.size());
}

std::string vertexText(int v) {
  std::string text = "vertex ";
  text += std::to_string(v);
  return text;
}

// ---- Seam refinement on coarse targets (section 4.4, Fig. 6d: the gap is triangulated between
// the two outlines, which works only where both outlines are about equally fine).

using Segment = std::array<Vector2d, 2>;

// R_in's boundary edges in the parameter domain.
std::vector<Segment> patchOutline(const TriMesh& canvas, const std::vector<int>& patchFaces,
                                  const std::vector<char>& patchSelected,
                                  const std::vector<Vector2d>& uv) {
  std::vector<Segment> edges;
  for (int f : patchFaces)
    for (auto h : canvas.fh_range(TriMesh::FaceHandle(f))) {
      const auto other = canvas.opposite_face_handle(h);
      if (other.is_valid() && patchSelected[std::size_t(other.idx())]) continue;
      edges.push_back({uv[std::size_t(canvas.from_vertex_handle(h).idx())],
                       uv[std::size_t(canvas.to_vertex_handle(h).idx())]});
    }
  return edges;
}

double meanLength(const std::vector<Segment>& edges) {
  double sum = 0;
  for (const auto& e : edges)
    sum += (e[1] - e[0]).norm();
  return edges.empty() ? 0 : sum / double(edges.size());
}

// R_in's outline bucketed on a uniform grid of the domain, so that a query costs the outline's
// length near it rather than the whole outline's.
class Outline {
 public:
  Outline(std::vector<Segment> edges, double cellSize) : edges_(std::move(edges)) {
    Eigen::AlignedBox2d box;
    for (const auto& e : edges_)
      box.extend(e[0]).extend(e[1]);
    corner_ = box.min();
    cell_ = cellSize > 0 ? cellSize : 1;
    // A bounded grid: at most about 4 cells per edge, however small the cells asked for.
    const double cells = std::max(1.0, box.sizes().prod() / (cell_ * cell_));
    if (cells > 4.0 * double(edges_.size()) + 16)
      cell_ *= std::sqrt(cells / (4.0 * double(edges_.size()) + 16));
    nx_ = int(box.sizes().x() / cell_) + 1;
    ny_ = int(box.sizes().y() / cell_) + 1;
    std::vector<int> count(std::size_t(nx_) * std::size_t(ny_) + 1, 0);
    forEachCell([&](std::size_t c, int) { ++count[c + 1]; });
    std::partial_sum(count.begin(), count.end(), count.begin());
    start_ = count;
    entries_.resize(std::size_t(start_.back()));
    forEachCell([&](std::size_t c, int e) { entries_[std::size_t(count[c]++)] = e; });
  }

  std::size_t edgeCount() const { return edges_.size(); }

  // Whether the bounding box of an outline edge meets `box`.
  bool meets(const Eigen::AlignedBox2d& box) const {
    const int i0 = cellX(box.min().x()), i1 = cellX(box.max().x());
    const int j0 = cellY(box.min().y()), j1 = cellY(box.max().y());
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        for (int k = start_[cellIndex(i, j)]; k < start_[cellIndex(i, j) + 1]; ++k) {
          const Segment& e = edges_[std::size_t(entries_[std::size_t(k)])];
          if (Eigen::AlignedBox2d(e[0].cwiseMin(e[1]), e[0].cwiseMax(e[1])).intersects(box))
            return true;
        }
    return false;
  }

  // Whether u lies inside the outline or within `margin` of it.
  bool covers(const Vector2d& u, double margin) const { return encloses(u) || near(u, margin); }

  // Whether an outline edge passes within `margin` of u.
  bool near(const Vector2d& u, double margin) const {
    const int i0 = cellX(u.x() - margin), i1 = cellX(u.x() + margin);
    const int j0 = cellY(u.y() - margin), j1 = cellY(u.y() + margin);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        for (int k = start_[cellIndex(i, j)]; k < start_[cellIndex(i, j) + 1]; ++k) {
          const Segment& e = edges_[std::size_t(entries_[std::size_t(k)])];
          const Vector2d d = e[1] - e[0];
          const double t =
              d.squaredNorm() > 0 ? std::clamp((u - e[0]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0;
          if ((e[0] + t * d - u).squaredNorm() <= margin * margin) return true;
        }
    return false;
  }

  // Whether u lies inside the outline (even-odd: inside R_in, not in one of its holes). Counts
  // the crossings of a ray towards +x, each in the one cell that holds its crossing point.
  bool encloses(const Vector2d& u) const {
    const double y = u.y();
    if (y < corner_.y() || y > corner_.y() + cell_ * ny_) return false;
    const int j = cellY(y);
    bool inside = false;
    for (int i = cellX(u.x()); i < nx_; ++i)
      for (int k = start_[cellIndex(i, j)]; k < start_[cellIndex(i, j) + 1]; ++k) {
        const Segment& e = edges_[std::size_t(entries_[std::size_t(k)])];
        if ((e[0].y() > y) == (e[1].y() > y)) continue;
        const double x = e[0].x() + (y - e[0].y()) / (e[1].y() - e[0].y()) * (e[1].x() - e[0].x());
        if (x > u.x() && cellX(x) == i) inside = !inside;
      }
    return inside;
  }

 private:
  int cellX(double x) const {
    return std::clamp(int(std::floor((x - corner_.x()) / cell_)), 0, nx_ - 1);
  }
  int cellY(double y) const {
    return std::clamp(int(std::floor((y - corner_.y()) / cell_)), 0, ny_ - 1);
  }
  std::size_t cellIndex(int i, int j) const {
    return std::size_t(j) * std::size_t(nx_) + std::size_t(i);
  }

  template <typename F>
  void forEachCell(F&& f) const {
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const Segment& s = edges_[e];
      const int i0 = cellX(std::min(s[0].x(), s[1].x())), i1 = cellX(std::max(s[0].x(), s[1].x()));
      const int j0 = cellY(std::min(s[0].y(), s[1].y())), j1 = cellY(std::max(s[0].y(), s[1].y()));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
          f(cellIndex(i, j), int(e));
    }
  }

  std::vector<Segment> edges_;
  Vector2d corner_ = Vector2d::Zero();
  double cell_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<int> start_;    // per cell, its first entry in entries_; one past the end
  std::vector<int> entries_;  // edge ids, cell by cell
};

// Refined target edges near dQ end up no longer than this many times R_in's mean boundary edge:
// bisection leaves them between half and all of it, about as long as R_in's on average.
constexpr double kRefinedEdgeRatio = 1.5;

// The mean length in the domain of the edges of the removed target faces that dQ crosses (with
// an uncovered corner): how fine the target is where the seam will be.
double crossingEdgeLength(const TriMesh& targetCanvas, const std::vector<int>& removedCanvasFaces,
                          const std::vector<char>& covered, const std::vector<Vector2d>& uv) {
  double sum = 0;
  std::size_t count = 0;
  for (int f : removedCanvasFaces) {
    const auto h0 = targetCanvas.halfedge_handle(TriMesh::FaceHandle(f));
    const auto h1 = targetCanvas.next_halfedge_handle(h0),
               h2 = targetCanvas.next_halfedge_handle(h1);
    const std::size_t a = std::size_t(targetCanvas.from_vertex_handle(h0).idx()),
                      b = std::size_t(targetCanvas.from_vertex_handle(h1).idx()),
                      c = std::size_t(targetCanvas.from_vertex_handle(h2).idx());
    if (covered[a] && covered[b] && covered[c]) continue;
    sum += (uv[a] - uv[b]).norm() + (uv[b] - uv[c]).norm() + (uv[c] - uv[a]).norm();
    count += 3;
  }
  return count ? sum / double(count) : 0;
}

// The target faces around dQ, refined: the removed faces and every face sharing a corner with
// one, so that every corner of a removed face has its whole fan here and the band's own boundary
// (which is never split: the faces beyond it stay as they are) lies beyond the seam. Its target
// vertices and faces are those of the outside's local part (StitchOutside::local).
struct SeamBand {
  TriMesh mesh;                   // the band's faces, bisected near R_in's outline
  std::vector<int> localVertex;   // band vertex -> local vertex, -1 where the refinement added it
  std::vector<Vector2d> uv;       // band vertex -> its place in the domain
  std::vector<char> covered;      // band vertex -> its faces are removed (see refineSeamBand)
  std::vector<char> kept;         // band face -> stays in the result
  std::vector<int> localFaces;    // the local faces of the band, increasing
  std::size_t replacedFaces = 0;  // target faces bisected or removed
};

Eigen::AlignedBox2d uvBox(const SeamBand& band, TriMesh::FaceHandle f, double margin) {
  Eigen::AlignedBox2d box;
  for (auto v : band.mesh.fv_range(f))
    box.extend(band.uv[std::size_t(v.idx())]);
  return Eigen::AlignedBox2d(box.min().array() - margin, box.max().array() + margin);
}

// Bisects the band's faces near R_in's outline whose longest edge is longer than `limit` in the
// domain, by longest-edge bisection (Rivara's LEPP): a face's longest edge is split once it is the
// longest edge of the face across it too, else that face is bisected first; a split halves both
// faces of the edge, so the band stays conforming, and along longest edges, so the faces keep
// their shape. The band's own boundary is never split (the faces beyond it stay as they are): a
// path that reaches it splits its last edge inside instead. A new vertex lies at the edge's
// midpoint, on the target's face, and is covered when both ends are, or when R_in's outline
// covers it (see refineSeamBand). `originalChanged` marks the band's first faces split. Throws
// StitchError if the splits outgrow `maxSplits`.
void bisectNearOutline(SeamBand& band, const Outline& outline, double limit, std::size_t maxSplits,
                       std::vector<char>& originalChanged) {
  TriMesh& mesh = band.mesh;
  const double margin = limit / 2;
  using Key = std::pair<double, int>;  // an edge's length, then its index: a total order
  auto key = [&](TriMesh::EdgeHandle e) -> Key {
    const auto h = mesh.halfedge_handle(e, 0);
    return {(band.uv[std::size_t(mesh.to_vertex_handle(h).idx())] -
             band.uv[std::size_t(mesh.from_vertex_handle(h).idx())])
                .norm(),
            e.idx()};
  };
  auto longest = [&](TriMesh::FaceHandle f) {
    TriMesh::EdgeHandle best;
    for (auto e : mesh.fe_range(f))
      if (!best.is_valid() || key(e) > key(best)) best = e;
    return best;
  };
  auto wanted = [&](TriMesh::FaceHandle f) {
    return key(longest(f)).first > limit && outline.meets(uvBox(band, f, limit));
  };
  auto split = [&](TriMesh::EdgeHandle e) {
    const auto h = mesh.halfedge_handle(e, 0);
    const auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
    for (auto side : {h, mesh.opposite_halfedge_handle(h)}) {
      const auto f = mesh.face_handle(side);
      if (std::size_t(f.idx()) < originalChanged.size()) originalChanged[std::size_t(f.idx())] = 1;
    }
    const Vector2d uv = 0.5 * (band.uv[std::size_t(a.idx())] + band.uv[std::size_t(b.idx())]);
    const bool coveredA = band.covered[std::size_t(a.idx())],
               coveredB = band.covered[std::size_t(b.idx())];
    const auto v = mesh.add_vertex(0.5 * (mesh.point(a) + mesh.point(b)));
    band.localVertex.push_back(-1);
    band.uv.push_back(uv);
    band.covered.push_back((coveredA && coveredB) || outline.covers(uv, margin));
    mesh.split(e, v);
    return v;
  };

  std::priority_queue<Key> queue;  // faces to bisect, by their longest edge, longest first
  auto push = [&](TriMesh::FaceHandle f) {
    if (wanted(f)) queue.push({key(longest(f)).first, f.idx()});
  };
  for (auto f : mesh.faces())
    push(f);
  std::size_t splits = 0;
  while (!queue.empty()) {
    const auto [length, index] = queue.top();
    queue.pop();
    const auto f = TriMesh::FaceHandle(index);
    if (key(longest(f)).first != length || !wanted(f)) continue;  // bisected since, or done
    // The longest-edge propagation path from f to its terminal edge.
    TriMesh::EdgeHandle edge = longest(f), inside;
    for (auto face = f;;) {
      if (mesh.is_boundary(edge)) {
        edge = inside;  // the band's edge: split the last edge of the path inside the band
        break;
      }
      const auto h = mesh.halfedge_handle(edge, 0);
      const auto across =
          mesh.face_handle(mesh.face_handle(h) == face ? mesh.opposite_halfedge_handle(h) : h);
      const auto next = longest(across);
      if (next == edge) break;  // terminal: the longest edge of both its faces
      inside = edge;
      edge = next;
      face = across;
    }
    if (!edge.is_valid()) continue;  // f's own longest edge is the band's edge
    if (++splits > maxSplits) throw StitchError("the seam band refinement does not end");
    const auto v = split(edge);
    for (auto g : mesh.vf_range(v))
      push(g);
    push(f);  // bisected itself, or only a face on its path
  }
}

// Whether the local part has faces around band vertex v that the band does not hold and that
// stay (`keptLocal`: the local faces not removed; the removed faces inside the seam are no
// part of the band).
bool openInBand(const SeamBand& band, const TriMesh& local, const std::vector<char>& keptLocal,
                TriMesh::VertexHandle v) {
  const int m = band.localVertex[std::size_t(v.idx())];
  if (m < 0) return false;  // added inside the band: its fan is the band's
  for (auto f : local.vf_range(TriMesh::VertexHandle(m)))
    if (keptLocal[std::size_t(f.idx())] &&
        !std::binary_search(band.localFaces.begin(), band.localFaces.end(), f.idx()))
      return true;
  return false;
}

// The seam band of the removed canvas faces, refined near R_in's outline down to edges of
// `limit`, its faces that touch a covered vertex removed and the rest made manifold. A band vertex
// is covered when Q covers it (a target vertex of the region), when it was added on an edge
// between two covered ones, or when it lies inside R_in's outline or within limit / 2 of it: a
// kept edge near the outline, at most `limit` long, then never crosses it (each of its points
// lies within limit / 2 of an end), so the target's outline and R_in's do not overlap and the
// strips between them do not fold. Throws StitchError where making the band manifold would reach
// beyond it.
SeamBand refineSeamBand(const std::vector<int>& removedCanvasFaces, const Outline& outline,
                        double limit, const std::vector<char>& coveredCanvas,
                        const Parameterization& target, const StitchBase& base,
                        const std::vector<char>& keptLocal) {
  const TriMesh& local = base.outside->local;
  const TriMesh& targetCanvas = target.canvas->surface;
  SeamBand band;
  // Only the removed faces that dQ crosses (a corner uncovered) seed the band: those inside it
  // stay removed as they are, so that the band's cost follows the seam rather than the region.
  for (int f : removedCanvasFaces) {
    bool crossed = false;
    for (auto corner : targetCanvas.fv_range(TriMesh::FaceHandle(f)))
      crossed = crossed || !coveredCanvas[std::size_t(corner.idx())];
    if (!crossed) continue;
    for (auto corner : targetCanvas.fv_range(TriMesh::FaceHandle(f)))
      for (auto g : targetCanvas.vf_range(corner))
        band.localFaces.push_back(base.canvasFaceToLocal[std::size_t(g.idx())]);
  }
  std::sort(band.localFaces.begin(), band.localFaces.end());
  band.localFaces.erase(std::unique(band.localFaces.begin(), band.localFaces.end()),
                        band.localFaces.end());
  Submesh sub = extractSubmesh(local, band.localFaces);
  if (sub.unattachedFace >= 0) throw StitchError("the seam band is not a manifold");
  band.mesh = std::move(sub.surface);
  band.localVertex = std::move(sub.sourceVertex);
  for (int m : band.localVertex) {
    const int c = base.localToCanvas[std::size_t(m)];
    band.uv.push_back(target.uv[std::size_t(c)]);
    band.covered.push_back(coveredCanvas[std::size_t(c)] ||
                           outline.covers(band.uv.back(), limit / 2));
  }
  std::vector<char> changed(band.mesh.n_faces(), 0);
  // Longest-edge bisection stays a few faces deep along the outline: many times that is a runaway.
  const std::size_t maxSplits = 64 * (band.mesh.n_faces() + outline.edgeCount());
  bisectNearOutline(band, outline, limit, maxSplits, changed);

  band.kept.assign(band.mesh.n_faces(), 1);
  std::vector<int> removed;
  for (auto f : band.mesh.faces()) {
    bool touches = false;
    for (auto v : band.mesh.fv_range(f))
      touches = touches || band.covered[std::size_t(v.idx())];
    if (!touches) continue;
    band.kept[std::size_t(f.idx())] = 0;
    removed.push_back(f.idx());
  }
  removePinches(band.mesh, band.kept, removed);
  for (auto f : band.mesh.faces()) {
    if (band.kept[std::size_t(f.idx())]) continue;
    for (auto v : band.mesh.fv_range(f))
      if (openInBand(band, local, keptLocal, v))
        throw StitchError("the removed faces reach the edge of the seam band");
    if (std::size_t(f.idx()) < changed.size()) changed[std::size_t(f.idx())] = 1;
  }
  band.replacedFaces = std::size_t(std::count(changed.begin(), changed.end(), 1));
  return band;
}

// Adds the band's kept faces to `out`, which holds the rest of the target (`localInOut`: local
// vertex -> vertex of `out`, or -1). Target vertices `out` already has are reused; the others
// and the refinement's are added, with their local vertex (-1 for the refinement's) and domain
// point appended to `addedLocal` and `addedUv`. The faces go in breadth-first order from the band's
// edge, so that each meets the faces before it along an edge (add_face then never has to relink
// fans). Returns band vertex -> vertex of `out`, -1 where no kept face uses it; `added` counts the
// refinement's vertices added.
std::vector<int> addBand(TriMesh& out, const SeamBand& band, const std::vector<int>& localInOut,
                         std::vector<int>& addedLocal, std::vector<Vector2d>& addedUv,
                         std::size_t& added) {
  const TriMesh& mesh = band.mesh;
  std::vector<int> bandInOut(mesh.n_vertices(), -1);
  for (std::size_t v = 0; v < band.localVertex.size(); ++v)
    if (band.localVertex[v] >= 0) bandInOut[v] = localInOut[std::size_t(band.localVertex[v])];
  std::vector<char> queued(mesh.n_faces(), 0);
  std::vector<int> order;
  auto enqueue = [&](TriMesh::FaceHandle f) {
    if (!f.is_valid() || !band.kept[std::size_t(f.idx())] || queued[std::size_t(f.idx())]) return;
    queued[std::size_t(f.idx())] = 1;
    order.push_back(f.idx());
  };
  for (auto f : mesh.faces())
    for (auto h : mesh.fh_range(f))
      if (mesh.is_boundary(mesh.opposite_halfedge_handle(h))) enqueue(f);
  std::size_t unreached = 0;  // faces before it are all queued or removed
  for (std::size_t next = 0;; ++next) {
    if (next == order.size()) {
      // Kept faces the band's edge does not reach through kept faces: go on from the first.
      while (unreached < mesh.n_faces() && (!band.kept[unreached] || queued[unreached]))
        ++unreached;
      if (unreached == mesh.n_faces()) break;
      enqueue(TriMesh::FaceHandle(int(unreached)));
    }
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(order[next])))
      enqueue(mesh.opposite_face_handle(h));
  }
  for (int f : order) {
    std::array<TriMesh::VertexHandle, 3> corners;
    int k = 0;
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f))) {
      int& o = bandInOut[std::size_t(v.idx())];
      if (o < 0) {
        o = out.add_vertex(mesh.point(v)).idx();
        added += band.localVertex[std::size_t(v.idx())] < 0;
        addedLocal.push_back(band.localVertex[std::size_t(v.idx())]);
        addedUv.push_back(band.uv[std::size_t(v.idx())]);
      }
      corners[std::size_t(k++)] = TriMesh::VertexHandle(o);
    }
    if (!out.add_face(corners[0], corners[1], corners[2]).is_valid())
      throw StitchError("the refined seam band could not be joined to the target");
  }
  return bandInOut;
}

}  // namespace

namespace {

// The target mesh a canvas lies on.
const TriMesh& meshOf(const Canvas& canvas) {
  return canvas.source ? canvas.source->surface : canvas.surface;
}

// Fills the base's maps between `target`'s canvas and its mesh.
void mapCanvas(StitchBase& base, const Parameterization& target) {
  if (!target.canvas) throw StitchError("the target parameterization has no canvas");
  const Canvas& canvas = *target.canvas;
  const TriMesh& mesh = meshOf(canvas);
  base.canvasToMesh = canvas.sourceVertex;
  base.canvasFaceToMesh = canvas.sourceFace;
  if (!canvas.source) {
    base.canvasToMesh.resize(canvas.surface.n_vertices());
    std::iota(base.canvasToMesh.begin(), base.canvasToMesh.end(), 0);
    base.canvasFaceToMesh.resize(canvas.surface.n_faces());
    std::iota(base.canvasFaceToMesh.begin(), base.canvasFaceToMesh.end(), 0);
  }
  if (base.canvasToMesh.size() != canvas.surface.n_vertices() ||
      base.canvasFaceToMesh.size() != canvas.surface.n_faces() ||
      target.uv.size() != canvas.surface.n_vertices())
    throw StitchError("the target canvas does not map its vertices and faces to the target mesh");
  for (int v : base.canvasToMesh)
    if (v < 0 || std::size_t(v) >= mesh.n_vertices())
      throw StitchError("the target canvas maps a vertex outside the target mesh");
  for (int f : base.canvasFaceToMesh)
    if (f < 0 || std::size_t(f) >= mesh.n_faces())
      throw StitchError("the target canvas maps a face outside the target mesh");
  base.meshToCanvas.assign(mesh.n_vertices(), -1);
  for (std::size_t c = 0; c < base.canvasToMesh.size(); ++c)
    base.meshToCanvas[std::size_t(base.canvasToMesh[c])] = int(c);
}

}  // namespace

namespace {

// outside.local: the open faces and every face around their corners (`openVertex`: the corners),
// with its maps into outside.mesh (`inMesh`: how outside.mesh was appended, whose arrays the
// local part's append then reuses).
void addLocalPart(StitchOutside& outside, const TriMesh& targetMesh, AppendedFaces inMesh,
                  const std::vector<char>& openVertex, const std::vector<char>& open) {
  std::vector<char> near(targetMesh.n_faces(), 0);
  for (std::size_t v = 0; v < openVertex.size(); ++v)
    if (openVertex[v])
      for (auto f : targetMesh.vf_range(TriMesh::VertexHandle(int(v))))
        near[std::size_t(f.idx())] = 1;
  std::vector<int>& faces = outside.localFaceToMesh;
  for (std::size_t f = 0; f < near.size(); ++f)
    if (near[f]) faces.push_back(int(f));
  // Where each local face's edges and corners are in outside.mesh, in the order of its halfedges.
  AppendedFaces& joined = outside.localInMesh;
  std::vector<int> edgeAt, vertexAt;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    joined.faceInOut.push_back(inMesh.faceInOut[std::size_t(faces[k])]);
    if (open[std::size_t(faces[k])]) outside.localOpenFaces.push_back(int(k));
    for (auto h : targetMesh.fh_range(TriMesh::FaceHandle(faces[k]))) {
      edgeAt.push_back(inMesh.edgeInOut[std::size_t(h.idx() / 2)]);
      vertexAt.push_back(inMesh.vertexInOut[std::size_t(targetMesh.to_vertex_handle(h).idx())]);
    }
  }
  // appendFaces keeps each halfedge's side and each face's halfedge order: a join through
  // `local` numbers what it adds as one through the target mesh would.
  AppendedFaces inLocal = appendFacesReusing(outside.local, targetMesh, faces, std::move(inMesh));
  outside.localVertexToMesh = std::move(inLocal.sourceVertex);
  const TriMesh& local = outside.local;
  joined.vertexInOut.assign(local.n_vertices(), -1);
  joined.edgeInOut.assign(local.n_edges(), -1);
  std::size_t corner = 0;
  for (auto f : local.faces())
    for (auto h : local.fh_range(f)) {
      joined.edgeInOut[std::size_t(h.idx() / 2)] = edgeAt[corner];
      joined.vertexInOut[std::size_t(local.to_vertex_handle(h).idx())] = vertexAt[corner++];
    }
}

}  // namespace

StitchOutside stitchOutside(const TriMesh& targetMesh, const std::vector<char>& open) {
  if (open.size() != targetMesh.n_faces())
    throw StitchError("the open part does not flag every target face");
  StitchOutside outside;
  std::vector<int> outsideFaces;
  for (std::size_t f = 0; f < open.size(); ++f)
    (open[f] ? outside.openMeshFaces : outsideFaces).push_back(int(f));
  AppendedFaces inMesh = appendFaces(outside.mesh, targetMesh, outsideFaces);
  std::vector<char> openVertex(targetMesh.n_vertices(), 0);
  for (int f : outside.openMeshFaces)
    for (auto v : targetMesh.fv_range(TriMesh::FaceHandle(f)))
      openVertex[std::size_t(v.idx())] = 1;
  const TriMesh& mesh = outside.mesh;
  for (auto v : mesh.vertices()) {
    if (!openVertex[std::size_t(inMesh.sourceVertex[std::size_t(v.idx())])]) continue;
    outside.borderVertices.push_back(v.idx());
    for (auto h : mesh.voh_range(v)) {
      outside.borderHalfedges.push_back(h.idx());
      outside.borderHalfedges.push_back(mesh.opposite_halfedge_handle(h).idx());
    }
  }
  std::sort(outside.borderHalfedges.begin(), outside.borderHalfedges.end());
  outside.borderHalfedges.erase(
      std::unique(outside.borderHalfedges.begin(), outside.borderHalfedges.end()),
      outside.borderHalfedges.end());
  outside.meshVertex = std::move(inMesh.sourceVertex);
  addLocalPart(outside, targetMesh, std::move(inMesh), openVertex, open);
  return outside;
}

OpenCell openCellOf(const Canvas& canvas) {
  double farthest = 0;
  for (auto v : canvas.surface.vertices())
    farthest = std::max(farthest, (pointOf(canvas.surface, v) - canvas.originPoint).norm());
  // R: the next power of 2^(1/4) at or above the farthest vertex, so that a drag's canvases,
  // whose extents differ a little, mostly share one.
  if (!(farthest > 1e-150 && farthest < 1e150)) return {};
  return openCellAt(int(std::ceil(4 * std::log2(farthest))), canvas.originPoint);
}

OpenCell openCellAt(int quarterOctaves, const Eigen::Vector3d& point) {
  if (!point.allFinite()) return {};
  const double radius = std::exp2(quarterOctaves / 4.0);
  OpenCell cell;
  cell.quarterOctaves = quarterOctaves;
  cell.side = radius / 4;
  Hasher key;
  key.u64(std::uint64_t(std::int64_t(quarterOctaves)));
  for (int axis = 0; axis < 3; ++axis) {
    const double index = std::floor(point[axis] / cell.side);
    if (!(std::abs(index) < 0x1p62)) return {};  // a canvas far smaller than its distance
    cell.center[axis] = (index + 0.5) * cell.side;
    key.u64(std::uint64_t(std::int64_t(index)));
  }
  cell.key = key.digest();
  cell.radius = radius + cell.side * std::sqrt(3.0) / 2;
  return cell;
}

OpenCell nextOpenCell(const OpenCell& cell, const Eigen::Vector3d& point,
                      const Eigen::Vector3d& direction) {
  if (cell.key == 0 || !direction.allFinite() || direction.isZero(0)) return {};
  const Eigen::Vector3d unit = direction.normalized();
  int firstAxis = -1;
  double first = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (unit[axis] == 0) continue;
    // How far along the direction the point is from the face ahead of it on this axis.
    const double face = cell.center[axis] + (unit[axis] > 0 ? 1 : -1) * cell.side / 2;
    const double along = std::max(0.0, (face - point[axis]) / unit[axis]);
    if (along < first) {
      first = along;
      firstAxis = axis;
    }
  }
  if (firstAxis < 0 || !(first < cell.side / 5)) return {};
  // Stepping from the centre to the centre beyond keeps clear of rounding at the face.
  Eigen::Vector3d beyond = cell.center;
  beyond[firstAxis] += unit[firstAxis] > 0 ? cell.side : -cell.side;
  return openCellAt(cell.quarterOctaves, beyond);
}

std::vector<char> openFaces(const TriMesh& mesh, const OpenCell& cell) {
  std::vector<char> near(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices())
    near[std::size_t(v.idx())] = (pointOf(mesh, v) - cell.center).norm() <= cell.radius;
  std::vector<char> open(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    bool all = true;
    for (auto v : mesh.fv_range(f))
      all = all && near[std::size_t(v.idx())];
    open[std::size_t(f.idx())] = all;
  }
  return open;
}

namespace {

// The base's maps between its canvas and its outside's local part, which holds the canvas.
void mapCanvasToLocal(StitchBase& base) {
  const StitchOutside& outside = *base.outside;
  auto localOf = [](const std::vector<int>& localToMesh, int m) {
    const auto it = std::lower_bound(localToMesh.begin(), localToMesh.end(), m);
    return it == localToMesh.end() || *it != m ? -1 : int(it - localToMesh.begin());
  };
  base.canvasFaceToLocal.clear();
  for (int f : base.canvasFaceToMesh) {
    base.canvasFaceToLocal.push_back(localOf(outside.localFaceToMesh, f));
    if (base.canvasFaceToLocal.back() < 0)
      throw StitchError("the target canvas reaches beyond the stitch's open part");
  }
  // A canvas vertex on no canvas face has no local vertex, and no paste uses it.
  base.localToCanvas.assign(outside.local.n_vertices(), -1);
  for (std::size_t c = 0; c < base.canvasToMesh.size(); ++c)
    if (const int l = localOf(outside.localVertexToMesh, base.canvasToMesh[c]); l >= 0)
      base.localToCanvas[std::size_t(l)] = int(c);
}

// Whether the outside's open part holds every face of the base's canvas.
bool holdsCanvas(const StitchOutside& outside, const StitchBase& base) {
  return std::all_of(base.canvasFaceToMesh.begin(), base.canvasFaceToMesh.end(), [&](int f) {
    return std::binary_search(outside.openMeshFaces.begin(), outside.openMeshFaces.end(), f);
  });
}

}  // namespace

StitchBase stitchBase(const Parameterization& target, std::shared_ptr<const DomainLocator> locator,
                      std::shared_ptr<const StitchOutside> outside) {
  StitchBase base;
  mapCanvas(base, target);
  base.locator = locator ? std::move(locator) : std::make_shared<const DomainLocator>(target);
  if (outside && holdsCanvas(*outside, base)) {
    base.outside = std::move(outside);
  } else {
    const TriMesh& mesh = meshOf(*target.canvas);
    std::vector<char> open(mesh.n_faces(), 0);
    for (int f : base.canvasFaceToMesh)
      open[std::size_t(f)] = 1;
    base.outside = std::make_shared<const StitchOutside>(stitchOutside(mesh, open));
  }
  mapCanvasToLocal(base);
  return base;
}

namespace {

// The outside of a cell's open part in a mesh, built once, by whichever comes first: its first
// caller, or a background thread that builds the cells a drag may enter next.
class OutsideBuild {
 public:
  OutsideBuild(MeshPtr mesh, const OpenCell& cell)
      : mesh_(std::move(mesh)),
        cell_(cell),
        task_([this] { return build(); }),
        outside_(task_.get_future().share()) {}

  // The origin of the last canvas that asked for this cell, where one did, and `origin` from now
  // on: which way a drag goes, for choosing the cell to build ahead. It changes no result.
  std::optional<Eigen::Vector3d> exchangeOrigin(const Eigen::Vector3d& origin) const {
    std::lock_guard lock(mutex_);
    return std::exchange(lastOrigin_, origin);
  }

  // Whether someone has run or is running the build.
  bool taken() const {
    std::lock_guard lock(mutex_);
    return taken_;
  }

  // Runs the build where no one has taken it; what it throws is kept for get().
  void run() const {
    {
      std::lock_guard lock(mutex_);
      if (taken_) return;
      taken_ = true;
    }
    task_();
  }

  // Runs the build or waits for it; what it throws passes through, to each caller. A build that
  // ran out of memory (perhaps ahead, beside other work) is made again by the caller.
  std::shared_ptr<const StitchOutside> get() const {
    run();
    try {
      return outside_.get();
    } catch (const std::bad_alloc&) {
      return build();
    }
  }

 private:
  std::shared_ptr<const StitchOutside> build() const {
    return std::make_shared<const StitchOutside>(
        stitchOutside(mesh_->surface, openFaces(mesh_->surface, cell_)));
  }

  const MeshPtr mesh_;
  const OpenCell cell_;
  mutable std::mutex mutex_;
  mutable bool taken_ = false;
  mutable std::optional<Eigen::Vector3d> lastOrigin_;
  mutable std::packaged_task<std::shared_ptr<const StitchOutside>()> task_;
  std::shared_future<std::shared_ptr<const StitchOutside>> outside_;
};

// Has the background thread build `ahead`, the cell a drag may enter next, on one core so that
// the drag keeps the others; `origin` is the last one the drag had before it enters the cell. A
// build whose entry the store has dropped by its turn is not run.
void buildAhead(const std::shared_ptr<const OutsideBuild>& ahead, const Eigen::Vector3d& origin) {
  if (!ahead) return;
  ahead->exchangeOrigin(origin);
  if (ahead->taken()) return;
  postBackgroundWork([weak = std::weak_ptr(ahead)] {
    const SerialOnThisThread serial;
    if (const auto build = weak.lock()) build->run();
  });
}

}  // namespace

std::shared_ptr<const StitchBase> derivedStitchBase(Context& ctx, std::string_view port) {
  const auto target = ctx.in<Parameterization>(port);
  const MeshPtr mesh = target->canvas ? target->canvas->source : nullptr;
  auto cellBuild = [&](const OpenCell& cell) -> std::shared_ptr<const OutsideBuild> {
    if (cell.key == 0 || !mesh) return nullptr;
    return ctx.derivedFrom("stitch_outside", {mesh}, cell.key,
                           [&] { return std::make_shared<const OutsideBuild>(mesh, cell); });
  };
  const auto base = ctx.derived("stitch_base", {port}, 0, [&] {
    // Per canvas, not per dab: finding the cell reads every canvas vertex.
    const OpenCell cell = target->canvas ? openCellOf(*target->canvas) : OpenCell{};
    const auto build = cellBuild(cell);
    const Eigen::Vector3d origin =
        target->canvas ? target->canvas->originPoint : Eigen::Vector3d::Zero();
    // A canvas before this one in the cell, or the last one before the cell, says which way the
    // drag goes; a brush's canvas stays, and builds nothing ahead.
    const auto before = build ? build->exchangeOrigin(origin) : std::nullopt;
    const auto shared = build ? build->get() : nullptr;
    auto made =
        std::make_shared<StitchBase>(stitchBase(*target, derivedLocator(ctx, port), shared));
    if (shared && made->outside == shared) {
      made->cell = cell;
      if (before) buildAhead(cellBuild(nextOpenCell(cell, origin, origin - *before)), origin);
    }
    return made;
  });
  // Each use keeps the cell's outside in the store, for the next canvas in the cell to find.
  cellBuild(base->cell);
  return base;
}

std::shared_ptr<Mesh> recyclePasteOutside(Context& ctx, std::string_view port,
                                          const std::shared_ptr<const StitchOutside>& outside) {
  auto mesh = ctx.recycle<Mesh, StitchOutside>(
                     port, [&](const StitchOutside& made) { return &made == outside.get(); })
                  .value;
  if (!mesh) return nullptr;
  restoreOutside(*outside, mesh->surface);
  mesh->vertexColors.clear();
  return mesh;
}

StitchResult stitchPaste(const Region2D& region, const Parameterization& source,
                         const TriMesh& draft, const Field2D* offset,
                         const Parameterization& target, const StitchBase* base,
                         const StitchOptions& options) {
  StitchResult result;
  StitchResult made =
      stitchPasteInto(result.mesh, region, source, draft, offset, target, base, false, options);
  result.patchVertices = made.patchVertices;
  result.removedFaces = made.removedFaces;
  result.refinedVertices = made.refinedVertices;
  result.gapTriangles = made.gapTriangles;
  result.seamLoops = made.seamLoops;
  result.map = std::move(made.map);
  result.startsWithOutside = made.startsWithOutside;
  return result;
}

namespace {

// Room for the whole target, the source canvas and the seam strips (an eighth of the open faces,
// more than any outline across the open part needs): a paste never outgrows it.
std::size_t pasteVertexRoom(const TriMesh& targetMesh, const TriMesh& sourceCanvas) {
  return targetMesh.n_vertices() + sourceCanvas.n_vertices();
}

void reserveForPaste(TriMesh& out, const TriMesh& targetMesh, const TriMesh& sourceCanvas,
                     std::size_t openFaces) {
  const std::size_t strips = openFaces / 8 + 1024;
  out.reserve(pasteVertexRoom(targetMesh, sourceCanvas),
              targetMesh.n_edges() + sourceCanvas.n_edges() + strips,
              targetMesh.n_faces() + sourceCanvas.n_faces() + strips);
}

}  // namespace

void copyOutside(const StitchOutside& outside, const TriMesh& targetMesh,
                 const TriMesh& sourceCanvas, TriMesh& out) {
  // Reserved first, the copy keeps the room (OpenMesh copies into the arrays it has).
  out.clear();
  reserveForPaste(out, targetMesh, sourceCanvas, outside.openMeshFaces.size());
  out = outside.mesh;
}

void restoreOutside(const StitchOutside& part, TriMesh& out) {
  const TriMesh& outside = part.mesh;
  if (out.n_vertices() < outside.n_vertices() || out.n_edges() < outside.n_edges() ||
      out.n_faces() < outside.n_faces())
    throw StitchError("the mesh to restore is smaller than the target's outside part");
  // Shrinking keeps the arrays' room: the next paste writes into memory already in use.
  out.resize(outside.n_vertices(), outside.n_edges(), outside.n_faces());
  for (int v : part.borderVertices)
    out.set_halfedge_handle(TriMesh::VertexHandle(v),
                            outside.halfedge_handle(TriMesh::VertexHandle(v)));
  for (int i : part.borderHalfedges) {
    const auto h = TriMesh::HalfedgeHandle(i);
    out.set_vertex_handle(h, outside.to_vertex_handle(h));
    out.set_face_handle(h, outside.face_handle(h));
    // Sets the next of h and the prev of its next; h's own prev is its predecessor's next.
    out.set_next_halfedge_handle(h, outside.next_halfedge_handle(h));
    out.set_next_halfedge_handle(outside.prev_halfedge_handle(h), h);
  }
}

namespace {

// The result of a paste that changes nothing: the target mesh, each vertex its own.
StitchResult keepTarget(TriMesh& out, const TriMesh& targetMesh) {
  StitchResult result;
  out = targetMesh;
  result.map.targetVertex.resize(targetMesh.n_vertices());
  std::iota(result.map.targetVertex.begin(), result.map.targetVertex.end(), 0);
  result.map.sourceVertex.assign(targetMesh.n_vertices(), -1);
  return result;
}

// R_in: the source faces with every corner in the region, made manifold.
struct PatchFaces {
  std::vector<char> selected;  // per source canvas face
  std::vector<int> faces;      // the selected ones, increasing
};

PatchFaces selectPatch(const TriMesh& canvas, const Region2D& region) {
  // Counting each face's corners in the region visits a face once per corner; the faces with
  // some corner out (along the outline) hold every vertex where R_in could be pinched.
  std::vector<char> inRegion(canvas.n_vertices(), 0);
  std::vector<char> cornersIn(canvas.n_faces(), 0);
  std::vector<int> touched;
  for (int v : region.sourceVertices) {
    if (inRegion[std::size_t(v)]) continue;
    inRegion[std::size_t(v)] = 1;
    for (auto f : canvas.vf_range(TriMesh::VertexHandle(v)))
      if (cornersIn[std::size_t(f.idx())]++ == 0) touched.push_back(f.idx());
  }
  PatchFaces patch;
  patch.selected.assign(canvas.n_faces(), 0);
  std::vector<int> alongOutline;
  for (int f : touched) {
    const bool whole = cornersIn[std::size_t(f)] == 3;
    patch.selected[std::size_t(f)] = whole;
    if (!whole) alongOutline.push_back(f);
  }
  removePinches(canvas, patch.selected, alongOutline);
  patch.faces = selectedFaces(patch.selected);
  return patch;
}

// The target faces the paste replaces: those of its canvas that touch a covered vertex.
// Faces are those of the base's local part (StitchOutside::local), which holds the canvas' faces
// and their neighbours: the cut's arrays follow the open part, not the target.
struct TargetCut {
  std::vector<char> covered;            // per target canvas vertex: in Q
  std::vector<char> kept;               // per local face
  std::vector<int> removedFaces;        // local faces
  std::vector<int> removedCanvasFaces;  // the same faces of the target canvas
};

TargetCut cutTarget(const Region2D& region, const Parameterization& target, const StitchBase& base,
                    const TriMesh& targetMesh) {
  const TriMesh& targetCanvas = target.canvas->surface;
  if (base.canvasToMesh.size() != targetCanvas.n_vertices() ||
      base.canvasFaceToMesh.size() != targetCanvas.n_faces() ||
      base.meshToCanvas.size() != targetMesh.n_vertices() ||
      base.canvasFaceToLocal.size() != targetCanvas.n_faces() ||
      base.localToCanvas.size() != base.outside->local.n_vertices())
    throw StitchError("the stitch base was made for another target canvas");
  std::vector<char> outerBoundary(targetCanvas.n_vertices(), 0);
  for (int v : target.canvas->boundary)
    outerBoundary[std::size_t(v)] = 1;
  TargetCut cut;
  cut.covered.assign(targetCanvas.n_vertices(), 0);
  for (int v : region.targetVertices) {
    // Vertices of the canvas' inner loops (holes of the target mesh) may be covered: a fill
    // replaces the faces around them.
    if (outerBoundary[std::size_t(v)]) {
      throw StitchError("the region reaches the edge of the target canvas at target " +
                        vertexText(base.canvasToMesh[std::size_t(v)]) +
                        ": paint away from it or grow the target canvas");
    }
    cut.covered[std::size_t(v)] = 1;
  }
  cut.kept.assign(base.outside->local.n_faces(), 1);
  for (int v : region.targetVertices)
    for (auto f : targetCanvas.vf_range(TriMesh::VertexHandle(v))) {
      const int localFace = base.canvasFaceToLocal[std::size_t(f.idx())];
      char& k = cut.kept[std::size_t(localFace)];
      if (k) {
        cut.removedFaces.push_back(localFace);
        cut.removedCanvasFaces.push_back(f.idx());
      }
      k = 0;
    }
  return cut;
}

// Twice the signed area of the domain triangle (a, b, c): positive where it turns left.
double turn(const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// The halfedge of target canvas face `face` through which the domain segment (a, b) leaves it, or
// an invalid one where b lies in the face (or on its border). `entered` is never the way out.
TriMesh::HalfedgeHandle exitOf(const TriMesh& canvas, const std::vector<Vector2d>& uv, int face,
                               const Segment& segment, TriMesh::HalfedgeHandle entered) {
  for (auto h : canvas.fh_range(TriMesh::FaceHandle(face))) {
    if (h == entered) continue;
    const Vector2d& p = uv[std::size_t(canvas.from_vertex_handle(h).idx())];
    const Vector2d& q = uv[std::size_t(canvas.to_vertex_handle(h).idx())];
    const Vector2d& r =
        uv[std::size_t(canvas.to_vertex_handle(canvas.next_halfedge_handle(h)).idx())];
    const double inside = turn(p, q, r);
    const bool beyond = inside > 0 ? turn(p, q, segment[1]) < 0 : turn(p, q, segment[1]) > 0;
    const double sideP = turn(segment[0], segment[1], p), sideQ = turn(segment[0], segment[1], q);
    if (beyond && !(sideP > 0 && sideQ > 0) && !(sideP < 0 && sideQ < 0)) return h;
  }
  return TriMesh::HalfedgeHandle();
}

// Removes, besides, the target faces that R_in's outline passes through, each outline edge walked
// through the target canvas in the domain from the face holding its first end: a target face with
// no corner in Q may still hold part of R_in near dQ (on a target as coarse as the region is
// small, a whole region), and a kept face under the patch would overlap it, or its outline cross
// R_in's where the gap is triangulated.
void cutUnderOutline(TargetCut& cut, const std::vector<Segment>& outline, const StitchBase& base,
                     const Parameterization& target) {
  const TriMesh& canvas = target.canvas->surface;
  const auto remove = [&](int canvasFace) {
    const int localFace = base.canvasFaceToLocal[std::size_t(canvasFace)];
    char& kept = cut.kept[std::size_t(localFace)];
    if (!kept) return;
    kept = 0;
    cut.removedFaces.push_back(localFace);
    cut.removedCanvasFaces.push_back(canvasFace);
  };
  for (const Segment& edge : outline) {
    const DomainHit hit = base.locator->locate(edge[0]);
    if (!hit.inside) continue;
    int face = hit.face;
    TriMesh::HalfedgeHandle entered;
    for (std::size_t step = 0; step < canvas.n_faces(); ++step) {
      remove(face);
      const TriMesh::HalfedgeHandle exit = exitOf(canvas, target.uv, face, edge, entered);
      if (!exit.is_valid() || canvas.is_boundary(canvas.opposite_halfedge_handle(exit))) break;
      entered = canvas.opposite_halfedge_handle(exit);
      face = canvas.face_handle(entered).idx();
    }
  }
}

// The longest edge the seam refinement leaves along dQ, or 0 where the target is fine enough
// there (see StitchOptions::seamRefinementRatio).
double refinementLimit(const std::vector<Segment>& outline, const TargetCut& cut,
                       const Parameterization& target, double refinementRatio) {
  if (refinementRatio <= 0) return 0;
  const double sourceEdge = meanLength(outline);
  if (sourceEdge <= 0 || crossingEdgeLength(target.canvas->surface, cut.removedCanvasFaces,
                                            cut.covered, target.uv) <= refinementRatio * sourceEdge)
    return 0;
  return kRefinedEdgeRatio * sourceEdge;
}

// Vertex of `out` -> target mesh vertex: the outside part's vertices first where `out` starts with
// it, then those added after them (-1 for the refinement's).
struct OutToMesh {
  const std::vector<int>* outside = nullptr;  // StitchOutside::meshVertex, or null
  std::vector<int> added;

  int operator()(int v) const {
    const std::size_t first = outside ? outside->size() : 0;
    return std::size_t(v) < first ? (*outside)[std::size_t(v)] : added[std::size_t(v) - first];
  }
};

// The kept target faces in `out`: the base's outside part, copied whole (unless `out` holds it
// already), with the kept open faces joined to it through the local part; or, where making the
// cut manifold reached beyond the open part (`keptMesh`: per target mesh face), every kept face
// appended afresh. The removed faces and the corners they are seeded from are the local part's,
// or the target mesh's in the second case (`cutMesh`).
struct TargetPart {
  const TriMesh* cutMesh = nullptr;
  std::vector<int> cutInOut;  // vertex of cutMesh -> vertex of `out`, -1 where no kept face uses it
  std::vector<int> removedFaces;  // the faces of cutMesh removed, increasing
  OutToMesh outToMesh;  // its `outside` set where `out` starts with the base's outside part
};

// `out` holds the outside part: the kept open faces joined to it.
TargetPart joinToOutside(TriMesh& out, const StitchOutside& outside,
                         const std::vector<char>& kept) {
  TargetPart part;
  std::vector<int> keptFaces;
  for (int f : outside.localOpenFaces)
    (kept[std::size_t(f)] ? keptFaces : part.removedFaces).push_back(f);
  AppendedFaces joined = joinFaces(out, outside.local, keptFaces, outside.localInMesh);
  part.cutMesh = &outside.local;
  part.cutInOut = std::move(joined.vertexInOut);
  part.outToMesh.outside = &outside.meshVertex;
  for (int local : joined.sourceVertex)
    part.outToMesh.added.push_back(outside.localVertexToMesh[std::size_t(local)]);
  return part;
}

TargetPart addTargetPart(TriMesh& out, const TriMesh& targetMesh, const TriMesh& sourceCanvas,
                         const StitchBase& base, const std::vector<char>& kept,
                         const std::vector<char>* keptMesh, bool outHoldsOutside) {
  // Copied connectivity, not add_face face by face, which takes several times longer on a large
  // target; with room for the patch and the seam strips.
  const StitchOutside& outside = *base.outside;
  auto reserve = [&] {
    reserveForPaste(out, targetMesh, sourceCanvas, outside.openMeshFaces.size());
  };
  if (!keptMesh) {
    if (!outHoldsOutside) {
      // Reserved first, the copy keeps the room (OpenMesh copies into the arrays it has).
      reserve();
      out = outside.mesh;
    }
    return joinToOutside(out, outside, kept);
  }
  TargetPart part;
  std::vector<int> keptFaces;
  for (std::size_t f = 0; f < keptMesh->size(); ++f)
    ((*keptMesh)[f] ? keptFaces : part.removedFaces).push_back(int(f));
  out.clear();
  reserve();
  AppendedFaces all = appendFaces(out, targetMesh, keptFaces);
  part.cutMesh = &targetMesh;
  part.cutInOut = std::move(all.vertexInOut);
  part.outToMesh.added = std::move(all.sourceVertex);
  return part;
}

// Makes the kept faces of the cut one fan at each vertex (removePinches) in the local part. Where
// that removes a face beyond the open part, whose far corners the local part does not surround,
// returns the kept faces of the whole target mesh instead, made manifold there.
std::optional<std::vector<char>> removeCutPinches(TargetCut& cut, const StitchOutside& outside,
                                                  const TriMesh& targetMesh) {
  removePinches(outside.local, cut.kept, cut.removedFaces);
  std::size_t removedOpen = 0;
  for (int f : outside.localOpenFaces)
    removedOpen += !cut.kept[std::size_t(f)];
  if (removedOpen == std::size_t(std::count(cut.kept.begin(), cut.kept.end(), 0)))
    return std::nullopt;
  // The cut as it was before, on the target mesh (removePinches leaves its candidates as they are).
  std::vector<char> keptMesh(targetMesh.n_faces(), 1);
  std::vector<int> removed;
  for (int f : cut.removedFaces) {
    removed.push_back(outside.localFaceToMesh[std::size_t(f)]);
    keptMesh[std::size_t(removed.back())] = 0;
  }
  removePinches(targetMesh, keptMesh, removed);
  return keptMesh;
}

// Where the seam loops are traced from: the vertices of `out` at a corner of a removed face
// (a removed face of the refined band, whose kept faces are added to `out` first), and where in
// the domain the vertices the band adds lie.
struct SeamSeeds {
  std::vector<int> vertices;     // vertices of `out`
  int firstBandVertex = 0;       // the first vertex of `out` the band added
  std::vector<Vector2d> bandUv;  // vertex firstBandVertex + i of `out` -> its place in the domain
};

SeamSeeds removedFaceSeeds(const TriMesh& out, const TargetPart& part) {
  SeamSeeds seeds;
  seeds.firstBandVertex = int(out.n_vertices());
  for (int f : part.removedFaces)
    for (auto corner : part.cutMesh->fv_range(TriMesh::FaceHandle(f)))
      seeds.vertices.push_back(part.cutInOut[std::size_t(corner.idx())]);
  return seeds;
}

SeamSeeds addBandSeeds(TriMesh& out, const SeamBand& band, const StitchOutside& outside,
                       TargetPart& part, std::size_t& refinedVertices) {
  if (part.cutMesh != &outside.local) throw StitchError("the seam band was cut beyond its part");
  SeamSeeds seeds;
  seeds.firstBandVertex = int(out.n_vertices());
  std::vector<int> bandLocal;
  const std::vector<int> bandInOut =
      addBand(out, band, part.cutInOut, bandLocal, seeds.bandUv, refinedVertices);
  for (int local : bandLocal)
    part.outToMesh.added.push_back(local < 0 ? -1 : outside.localVertexToMesh[std::size_t(local)]);
  for (auto f : band.mesh.faces())
    if (!band.kept[std::size_t(f.idx())])
      for (auto corner : band.mesh.fv_range(f))
        seeds.vertices.push_back(bandInOut[std::size_t(corner.idx())]);
  return seeds;
}

// The seam loops: the boundary loops of the target part through a seed, traced before the patch
// is added.
std::vector<DomainLoop> traceSeams(const TriMesh& out, const SeamSeeds& seeds,
                                   const OutToMesh& outToMesh, const StitchBase& base,
                                   const Parameterization& target) {
  auto uvInDomain = [&](int v) -> Vector2d {
    if (v >= seeds.firstBandVertex) return seeds.bandUv[std::size_t(v - seeds.firstBandVertex)];
    const int canvasVertex = base.meshToCanvas[std::size_t(outToMesh(v))];
    if (canvasVertex < 0) {
      throw StitchError(
          "the region reaches the edge of the target canvas: paint away from "
          "it or grow the target canvas");
    }
    return target.uv[std::size_t(canvasVertex)];
  };
  std::vector<DomainLoop> seams;
  std::unordered_set<int> traced;  // a few loops in a large mesh
  for (int o : seeds.vertices) {
    if (o < 0 || !out.is_boundary(TriMesh::VertexHandle(o))) continue;
    for (auto start : out.voh_range(TriMesh::VertexHandle(o))) {
      if (!out.is_boundary(start) || traced.count(start.idx())) continue;
      DomainLoop loop;
      auto h = start;
      do {
        traced.insert(h.idx());
        const int v = out.from_vertex_handle(h).idx();
        loop.uv.push_back(uvInDomain(v));
        loop.vertices.push_back(v);
        h = out.next_halfedge_handle(h);
      } while (h != start);
      seams.push_back(std::move(loop));
    }
  }
  return seams;
}

// R_in appended to `out` after the target's vertices, at the source canvas' positions until
// placePatch, with its boundary loops.
struct PatchPart {
  AppendedFaces faces;
  std::vector<std::vector<int>> loops;  // vertices of `out`
};

PatchPart addPatch(TriMesh& out, const TriMesh& canvas, const std::vector<int>& patchFaces) {
  // Joined to nothing: the copy costs the region's size, not the canvas'.
  AppendedFaces nothing;
  nothing.vertexInOut.assign(canvas.n_vertices(), -1);
  nothing.edgeInOut.assign(canvas.n_edges(), -1);
  nothing.faceInOut.assign(canvas.n_faces(), -1);
  const int firstPatchHalfedge = int(out.n_halfedges());
  PatchPart patch;
  patch.faces = joinFaces(out, canvas, patchFaces, std::move(nothing));
  // The patch's halfedges are the last ones.
  std::vector<char> traced(out.n_halfedges() - std::size_t(firstPatchHalfedge), 0);
  for (int v = patch.faces.firstVertex; v < int(out.n_vertices()); ++v) {
    if (!out.is_boundary(TriMesh::VertexHandle(v))) continue;
    for (auto start : out.voh_range(TriMesh::VertexHandle(v))) {
      if (!out.is_boundary(start) || traced[std::size_t(start.idx() - firstPatchHalfedge)])
        continue;
      std::vector<int> loop;
      auto h = start;
      do {
        traced[std::size_t(h.idx() - firstPatchHalfedge)] = 1;
        loop.push_back(out.from_vertex_handle(h).idx());
        h = out.next_halfedge_handle(h);
      } while (h != start);
      patch.loops.push_back(std::move(loop));
    }
  }
  return patch;
}

// R_in's boundary loops with their places in the domain: the source parameterization's.
std::vector<DomainLoop> patchLoops(const PatchPart& patch, const Parameterization& source) {
  std::vector<DomainLoop> loops;
  for (const auto& ids : patch.loops) {
    DomainLoop& loop = loops.emplace_back();
    loop.vertices = ids;
    for (int v : ids)
      loop.uv.push_back(
          source
              .uv[std::size_t(patch.faces.sourceVertex[std::size_t(v - patch.faces.firstVertex)])]);
  }
  return loops;
}

// Pairs each boundary loop of R_in with the seam loop nearest to it in the domain and fills the
// strip between them (section 4.4, Fig. 6d). `targetVertex` maps the vertices of `out` to the
// target mesh, or -1.
void zipSeams(TriMesh& out, const std::vector<DomainLoop>& patch,
              const std::vector<DomainLoop>& seams, const std::vector<int>& targetVertex,
              int firstPatchVertex, bool refinedSeam) {
  if (patch.size() != seams.size()) {
    throw StitchError("the region has " + std::to_string(patch.size()) +
                      " boundary loops on the source but " + std::to_string(seams.size()) +
                      " on the target: paint a region whose outline both canvases hold whole");
  }
  std::vector<char> paired(seams.size(), 0);
  for (const auto& [ids, uv] : patch) {
    std::size_t best = seams.size();
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < seams.size(); ++s) {
      const double d = paired[s] ? bestDistance : meanNearestDistance(uv, seams[s].uv);
      if (d < bestDistance) {
        bestDistance = d;
        best = s;
      }
    }
    if (best == seams.size()) throw StitchError("two source loops pair with one seam loop");
    paired[best] = 1;
    const DomainZipMetric metric(uv, seams[best].uv);
    for (const auto& t : zipLoops(ids, seams[best].vertices, metric, refinedSeam)) {
      const auto face = out.add_face(TriMesh::VertexHandle(t[0]), TriMesh::VertexHandle(t[1]),
                                     TriMesh::VertexHandle(t[2]));
      if (!face.is_valid()) {
        const int near = targetVertex[std::size_t(t[2] < firstPatchVertex ? t[2] : t[0])];
        std::string text = "the seam strip folds onto itself near ";
        if (near >= 0) {
          text += "target ";
          text += vertexText(near);
        } else {
          text += "the refined seam";
        }
        text += ": the two outlines are too far apart or too jagged to join";
        throw StitchError(text);
      }
    }
  }
}

// The paste map's vertex arrays for the layout so far, written into `map`'s, with `room` for the
// paste's vertices (as its mesh has, so that a map kept for the next dab holds it): the target
// part's vertices, then R_in's from patch.firstVertex. Where `held` and the target part starts
// with the outside part, `map` is the map of an earlier paste into the same base that started
// with it, and its entries for the outside part stay as they are.
void mapVertices(PasteMap& map, const OutToMesh& toMesh, const AppendedFaces& patch, bool held,
                 std::size_t room) {
  const std::size_t first = toMesh.outside ? toMesh.outside->size() : 0;
  const std::size_t vertices = std::size_t(patch.firstVertex) + patch.sourceVertex.size();
  map.targetVertex.reserve(room);
  map.sourceVertex.reserve(room);
  if (!held || map.targetVertex.size() < first || map.sourceVertex.size() < first) {
    if (toMesh.outside) map.targetVertex.assign(toMesh.outside->begin(), toMesh.outside->end());
    map.sourceVertex.assign(first, -1);
  }
  map.targetVertex.resize(first);
  map.targetVertex.insert(map.targetVertex.end(), toMesh.added.begin(), toMesh.added.end());
  map.targetVertex.resize(vertices, -1);
  map.sourceVertex.resize(first);
  map.sourceVertex.resize(std::size_t(patch.firstVertex), -1);
  map.sourceVertex.insert(map.sourceVertex.end(), patch.sourceVertex.begin(),
                          patch.sourceVertex.end());
}

// A layout with nothing to paste: the target mesh, no loops.
OpenStitch keepTargetOpen(TriMesh& out, const TriMesh& targetMesh) {
  OpenStitch open;
  open.result = keepTarget(out, targetMesh);
  open.firstPatchVertex = open.result.firstPatchVertex = int(out.n_vertices());
  open.firstGapFace = int(out.n_faces());
  return open;
}

// stitchOpenLayoutInto, refining the seam band as StitchOptions::seamRefinementRatio says;
// `refined` tells whether it did.
OpenStitch openLayout(TriMesh& out, const Region2D& region, const Parameterization& source,
                      const Parameterization& target, const StitchBase* base, bool outHoldsOutside,
                      double refinementRatio, bool& refined, PasteMap* reuse) {
  refined = false;
  if (outHoldsOutside && (!base || out.n_vertices() != base->outside->mesh.n_vertices() ||
                          out.n_faces() != base->outside->mesh.n_faces()))
    throw StitchError("the mesh to build into does not hold the target's outside part");
  if (!outHoldsOutside) out.clear();
  if (!source.canvas || !target.canvas) throw StitchError("the parameterizations have no canvases");
  const TriMesh& canvas = source.canvas->surface;
  const TriMesh& targetMesh = meshOf(*target.canvas);
  try {
    const std::size_t targetCanvasVertices = target.canvas->surface.n_vertices();
    requireRegionOn(region, canvas.n_vertices(), &targetCanvasVertices);
  } catch (const std::invalid_argument& e) {
    throw StitchError(e.what());
  }
  if (region.empty()) return keepTargetOpen(out, targetMesh);
  const PatchFaces patch = selectPatch(canvas, region);
  if (patch.faces.empty()) return keepTargetOpen(out, targetMesh);

  std::optional<StitchBase> ownBase;
  if (!base) base = &ownBase.emplace(stitchBase(target));
  TargetCut cut = cutTarget(region, target, *base, targetMesh);
  std::vector<Segment> outline = patchOutline(canvas, patch.faces, patch.selected, source.uv);
  cutUnderOutline(cut, outline, *base, target);
  // On a target coarser than the source, the faces along dQ are refined first; the band they
  // form replaces its target faces, and the rest stay whole.
  const double limit = refinementLimit(outline, cut, target, refinementRatio);
  std::optional<SeamBand> band;
  if (limit > 0) {
    refined = true;
    band = refineSeamBand(cut.removedCanvasFaces, Outline(std::move(outline), 2 * limit), limit,
                          cut.covered, target, *base, cut.kept);
    for (int f : band->localFaces)
      cut.kept[std::size_t(f)] = 0;
  }
  const std::optional<std::vector<char>> keptMesh =
      band ? std::nullopt : removeCutPinches(cut, *base->outside, targetMesh);

  OpenStitch open;
  StitchResult& result = open.result;  // its mesh stays empty: the mesh is `out`
  TargetPart part = addTargetPart(out, targetMesh, canvas, *base, cut.kept,
                                  keptMesh ? &*keptMesh : nullptr, outHoldsOutside);
  result.startsWithOutside = part.outToMesh.outside != nullptr;
  result.removedFaces = band ? band->replacedFaces : part.removedFaces.size();
  const SeamSeeds seeds =
      band ? addBandSeeds(out, *band, *base->outside, part, result.refinedVertices)
           : removedFaceSeeds(out, part);
  open.targetLoops = traceSeams(out, seeds, part.outToMesh, *base, target);
  const PatchPart patchPart = addPatch(out, canvas, patch.faces);
  open.patchLoops = patchLoops(patchPart, source);
  open.firstPatchVertex = patchPart.faces.firstVertex;
  open.firstGapFace = int(out.n_faces());
  open.refinedSeam = band.has_value();
  result.patchVertices = patchPart.faces.sourceVertex.size();
  result.seamLoops = open.targetLoops.size();

  result.firstPatchVertex = patchPart.faces.firstVertex;
  if (reuse) result.map = std::move(*reuse);
  mapVertices(result.map, part.outToMesh, patchPart.faces, outHoldsOutside && reuse,
              pasteVertexRoom(targetMesh, canvas));
  return open;
}

// stitchLayoutInto, refining the seam band as StitchOptions::seamRefinementRatio says; `refined`
// tells whether it did.
StitchResult layoutInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                        const Parameterization& target, const StitchBase* base,
                        bool outHoldsOutside, double refinementRatio, bool& refined,
                        PasteMap* reuse) {
  OpenStitch open = openLayout(out, region, source, target, base, outHoldsOutside, refinementRatio,
                               refined, reuse);
  zipOpenStitch(out, open);
  return finishOpenStitch(out, std::move(open));
}

}  // namespace

OpenStitch stitchOpenLayoutInto(TriMesh& out, const Region2D& region,
                                const Parameterization& source, const Parameterization& target,
                                const StitchBase* base, bool outHoldsOutside,
                                const StitchOptions& options) {
  bool refined = false;
  try {
    return openLayout(out, region, source, target, base, outHoldsOutside,
                      options.seamRefinementRatio, refined, nullptr);
  } catch (const StitchError&) {
    if (!refined) throw;
  }
  return openLayout(out, region, source, target, base, false, 0, refined, nullptr);
}

void zipOpenStitch(TriMesh& out, const OpenStitch& open) {
  zipSeams(out, open.patchLoops, open.targetLoops, open.result.map.targetVertex,
           open.firstPatchVertex, open.refinedSeam);
}

StitchResult finishOpenStitch(const TriMesh& out, OpenStitch open) {
  StitchResult result = std::move(open.result);
  PasteMap& map = result.map;
  map.targetVertex.resize(out.n_vertices(), -1);
  map.sourceVertex.resize(out.n_vertices(), -1);
  map.seamFaces.resize(out.n_faces() - std::size_t(open.firstGapFace));
  std::iota(map.seamFaces.begin(), map.seamFaces.end(), open.firstGapFace);
  result.gapTriangles = map.seamFaces.size();
  return result;
}

StitchResult stitchLayoutInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                              const Parameterization& target, const StitchBase* base,
                              bool outHoldsOutside, const StitchOptions& options, PasteMap reuse) {
  bool refined = false;
  try {
    return layoutInto(out, region, source, target, base, outHoldsOutside,
                      options.seamRefinementRatio, refined, &reuse);
  } catch (const StitchError&) {
    if (!refined) throw;
  }
  // The refined band could not be made manifold or joined (rare: R_in's outline winds through a
  // coarse face): the paste without it, as good as a coarse target allows, from a fresh copy.
  return layoutInto(out, region, source, target, base, false, 0, refined, &reuse);
}

void requireDraftOf(const TriMesh& draft, const Parameterization& source) {
  if (!source.canvas) throw StitchError("the source parameterization has no canvas");
  const TriMesh& canvas = source.canvas->surface;
  if (draft.n_vertices() != canvas.n_vertices() || draft.n_faces() != canvas.n_faces())
    throw StitchError("the draft does not have the source canvas' vertices and faces");
}

void placePatch(TriMesh& out, const PasteMap& map, const Parameterization& source,
                const TriMesh& draft, const Field2D* offset, int firstPatchVertex) {
  requireDraftOf(draft, source);
  if (map.sourceVertex.size() != out.n_vertices())
    throw StitchError("the paste map does not describe the mesh to place the patch in");
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (std::size_t v = std::size_t(std::max(firstPatchVertex, 0)); v < map.sourceVertex.size();
       ++v) {
    const int c = map.sourceVertex[v];
    if (c < 0) continue;
    const auto& g = draft.point(TriMesh::VertexHandle(c));
    if (offset && !offset->sample(source.uv[std::size_t(c)], shift)) {
      throw StitchError("the offset membrane is undefined at source canvas " + vertexText(c) +
                        " of the region");
    }
    out.set_point(TriMesh::VertexHandle(int(v)),
                  {g[0] + shift.x(), g[1] + shift.y(), g[2] + shift.z()});
  }
}

StitchResult stitchPasteInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                             const TriMesh& draft, const Field2D* offset,
                             const Parameterization& target, const StitchBase* base,
                             bool outHoldsOutside, const StitchOptions& options) {
  requireDraftOf(draft, source);  // before the layout's work, not after it
  StitchResult result =
      stitchLayoutInto(out, region, source, target, base, outHoldsOutside, options);
  placePatch(out, result.map, source, draft, offset, result.firstPatchVertex);
  return result;
}

}  // namespace geobrush
