#include "stitch.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <optional>

#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

using Eigen::Vector2d;

// Selected faces around `v` that form more than one fan (the selection touches itself at v).
bool pinched(const TriMesh& mesh, TriMesh::VertexHandle v, const std::vector<char>& selected) {
  int fans = 0;
  bool previous = false, first = false, any = false;
  for (auto h : mesh.voh_range(v)) {
    const auto f = mesh.face_handle(h);
    const bool in = f.is_valid() && selected[std::size_t(f.idx())];
    if (!any) first = in;
    fans += in && any && !previous;
    previous = in;
    any = true;
  }
  // The circulation is a cycle: a fan that starts the round was not counted, unless it wraps.
  fans += first && !previous;
  return fans > 1;
}

// Deselects the faces around vertices where the selection is pinched, until none is: every
// vertex of the selection then has one fan of selected faces and the selection is a manifold.
void removePinches(const TriMesh& mesh, std::vector<char>& selected) {
  // A pinched vertex has faces on both sides of the selection, so it is a corner of a selected and
  // of an unselected face: the corners of the smaller of the two sets are the candidates.
  const auto count = std::size_t(std::count(selected.begin(), selected.end(), 1));
  const char side = count <= selected.size() / 2 ? 1 : 0;
  std::vector<int> candidates;
  for (auto f : mesh.faces())
    if (selected[std::size_t(f.idx())] == side)
      for (auto v : mesh.fv_range(f))
        candidates.push_back(v.idx());
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  while (!candidates.empty()) {
    std::vector<int> next;
    for (int v : candidates) {
      const auto vh = TriMesh::VertexHandle(v);
      if (!pinched(mesh, vh, selected)) continue;
      for (auto f : mesh.vf_range(vh))
        if (selected[std::size_t(f.idx())]) {
          selected[std::size_t(f.idx())] = 0;
          for (auto w : mesh.fv_range(f))
            next.push_back(w.idx());
        }
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    candidates = std::move(next);
  }
}

std::vector<int> selectedFaces(const std::vector<char>& selected) {
  std::vector<int> faces;
  for (std::size_t f = 0; f < selected.size(); ++f)
    if (selected[f]) faces.push_back(int(f));
  return faces;
}

// Boundary loops as vertex lists in the direction of their boundary halfedges.
std::vector<std::vector<int>> boundaryLoops(const TriMesh& mesh) {
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_boundary(start) || seen[std::size_t(start.idx())]) continue;
    std::vector<int> loop;
    auto h = start;
    do {
      seen[std::size_t(h.idx())] = 1;
      loop.push_back(mesh.from_vertex_handle(h).idx());
      h = mesh.next_halfedge_handle(h);
    } while (h != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

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

// Triangulates the strip between loop `a` and loop `b` (vertex ids of the combined mesh, uv
// alongside), both in the direction of their boundary halfedges. Walking a forwards and b
// backwards keeps every triangle's orientation consistent with both sides; at each step the
// shorter new edge in the parameter domain is taken.
std::vector<std::array<int, 3>> zip(const std::vector<int>& a, const std::vector<Vector2d>& uvA,
                                    const std::vector<int>& b, const std::vector<Vector2d>& uvB) {
  const std::size_t na = a.size(), nb = b.size();
  std::size_t start = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < nb; ++k) {
    const double d = (uvB[k] - uvA[0]).squaredNorm();
    if (d < best) {
      best = d;
      start = k;
    }
  }
  auto bAt = [&](std::size_t step) { return (start + nb - step % nb) % nb; };
  std::vector<std::array<int, 3>> triangles;
  std::size_t i = 0, j = 0;  // steps taken along a and along b
  while (i < na || j < nb) {
    const std::size_t ai = i % na, ai1 = (i + 1) % na, bj = bAt(j), bj1 = bAt(j + 1);
    const bool advanceA = j == nb || (i < na && (uvA[ai1] - uvB[bj]).squaredNorm() <=
                                                    (uvA[ai] - uvB[bj1]).squaredNorm());
    if (advanceA) {
      triangles.push_back({a[ai], a[ai1], b[bj]});
      ++i;
    } else {
      triangles.push_back({b[bj1], b[bj], a[ai]});
      ++j;
    }
  }
  return triangles;
}

std::string vertexText(int v) {
  std::string text = "vertex ";
  text += std::to_string(v);
  return text;
}

}  // namespace

StitchBase stitchBase(const Parameterization& target) {
  if (!target.canvas) throw StitchError("the target parameterization has no canvas");
  const Canvas& canvas = *target.canvas;
  StitchBase base;
  base.canvasToMesh = canvas.sourceVertex;
  if (!canvas.source) {
    base.canvasToMesh.resize(canvas.surface.n_vertices());
    std::iota(base.canvasToMesh.begin(), base.canvasToMesh.end(), 0);
    base.meshToOutside.assign(canvas.surface.n_vertices(), -1);
    return base;
  }
  const TriMesh& mesh = canvas.source->surface;
  if (base.canvasToMesh.size() != canvas.surface.n_vertices() ||
      canvas.sourceFace.size() != canvas.surface.n_faces() ||
      target.uv.size() != canvas.surface.n_vertices())
    throw StitchError("the target canvas does not map its vertices and faces to the target mesh");
  std::vector<char> inCanvas(mesh.n_faces(), 0);
  for (int f : canvas.sourceFace)
    inCanvas[std::size_t(f)] = 1;
  std::vector<int> outsideFaces;
  for (std::size_t f = 0; f < inCanvas.size(); ++f)
    if (!inCanvas[f]) outsideFaces.push_back(int(f));
  Submesh outside = extractSubmesh(mesh, outsideFaces);
  if (outside.unattachedFace >= 0) throw StitchError("the target mesh is not a manifold mesh");
  base.outside = std::move(outside.surface);
  base.meshToOutside.assign(mesh.n_vertices(), -1);
  for (std::size_t o = 0; o < outside.sourceVertex.size(); ++o)
    base.meshToOutside[std::size_t(outside.sourceVertex[o])] = int(o);
  return base;
}

StitchResult stitchPaste(const Region2D& region, const Parameterization& source,
                         const TriMesh& draft, const Field2D* offset,
                         const Parameterization& target, const StitchBase* base) {
  if (!source.canvas || !target.canvas) throw StitchError("the parameterizations have no canvases");
  const TriMesh& canvas = source.canvas->surface;
  if (draft.n_vertices() != canvas.n_vertices() || draft.n_faces() != canvas.n_faces())
    throw StitchError("the draft does not have the source canvas' vertices and faces");
  const TriMesh& targetMesh =
      target.canvas->source ? target.canvas->source->surface : target.canvas->surface;
  StitchResult result;
  if (region.empty()) {
    result.mesh = targetMesh;
    return result;
  }

  // R_in: the source faces with every corner in the region, made manifold.
  std::vector<char> inRegion(canvas.n_vertices(), 0);
  for (int v : region.sourceVertices)
    inRegion[std::size_t(v)] = 1;
  std::vector<char> patchSelected(canvas.n_faces(), 0);
  for (auto f : canvas.faces()) {
    bool all = true;
    for (auto v : canvas.fv_range(f))
      all = all && inRegion[std::size_t(v.idx())];
    patchSelected[std::size_t(f.idx())] = all;
  }
  removePinches(canvas, patchSelected);
  Submesh patch = extractSubmesh(canvas, selectedFaces(patchSelected));
  if (patch.sourceFace.empty()) {
    result.mesh = targetMesh;
    return result;
  }

  // The target: its part outside the canvas as it is, then the canvas faces that touch no covered
  // vertex, made manifold.
  std::optional<StitchBase> ownBase;
  if (!base) base = &ownBase.emplace(stitchBase(target));
  const TriMesh& targetCanvas = target.canvas->surface;
  std::vector<char> covered(targetCanvas.n_vertices(), 0);
  std::vector<char> outerBoundary(targetCanvas.n_vertices(), 0);
  for (int v : target.canvas->boundary)
    outerBoundary[std::size_t(v)] = 1;
  for (int v : region.targetVertices) {
    // Vertices of the canvas' inner loops (holes of the target mesh) may be covered: a fill
    // replaces the faces around them.
    if (outerBoundary[std::size_t(v)]) {
      throw StitchError("the region reaches the edge of the target canvas at target " +
                        vertexText(base->canvasToMesh[std::size_t(v)]) +
                        ": paint away from it or grow the target canvas");
    }
    covered[std::size_t(v)] = 1;
  }
  std::vector<char> kept(targetCanvas.n_faces(), 1);
  for (auto f : targetCanvas.faces())
    for (auto v : targetCanvas.fv_range(f))
      if (covered[std::size_t(v.idx())]) kept[std::size_t(f.idx())] = 0;
  removePinches(targetCanvas, kept);

  TriMesh& out = result.mesh;
  out = base->outside;
  // Room for the whole result, so that adding faces does not reallocate the arrays.
  const std::size_t faces = out.n_faces() + targetCanvas.n_faces() + 2 * patch.surface.n_faces();
  out.reserve(out.n_vertices() + targetCanvas.n_vertices() + patch.surface.n_vertices(),
              faces * 3 / 2 + 1024, faces);
  std::vector<int> canvasToOut(targetCanvas.n_vertices(), -1);
  std::vector<int> outToCanvas(out.n_vertices(), -1);
  for (std::size_t c = 0; c < canvasToOut.size(); ++c) {
    const int o = base->meshToOutside[std::size_t(base->canvasToMesh[c])];
    canvasToOut[c] = o;
    if (o >= 0) outToCanvas[std::size_t(o)] = int(c);
  }
  auto outVertex = [&](TriMesh::VertexHandle c) {
    int& o = canvasToOut[std::size_t(c.idx())];
    if (o < 0) {
      o = out.add_vertex(targetCanvas.point(c)).idx();
      outToCanvas.push_back(c.idx());
    }
    return TriMesh::VertexHandle(o);
  };
  std::vector<char> seamCanvasVertex(targetCanvas.n_vertices(), 0);
  for (auto f : targetCanvas.faces()) {
    if (!kept[std::size_t(f.idx())]) {
      ++result.removedFaces;
      for (auto v : targetCanvas.fv_range(f))
        seamCanvasVertex[std::size_t(v.idx())] = 1;
      continue;
    }
    std::array<TriMesh::VertexHandle, 3> corners;
    int k = 0;
    for (auto v : targetCanvas.fv_range(f))
      corners[std::size_t(k++)] = outVertex(v);
    if (!out.add_face(corners[0], corners[1], corners[2]).is_valid())
      throw StitchError("the target is not a manifold mesh around its canvas");
  }
  if (patch.unattachedFace >= 0) throw StitchError("the source region is not a manifold mesh");

  // The seam loops: boundary loops of the target through a vertex of a removed face, found
  // before the patch is added.
  std::vector<std::vector<int>> seams;
  std::vector<std::vector<Vector2d>> seamUv;
  std::vector<char> traced(out.n_halfedges(), 0);
  for (std::size_t c = 0; c < seamCanvasVertex.size(); ++c) {
    if (!seamCanvasVertex[c] || canvasToOut[c] < 0) continue;
    for (auto start : out.voh_range(TriMesh::VertexHandle(canvasToOut[c]))) {
      if (!out.is_boundary(start) || traced[std::size_t(start.idx())]) continue;
      std::vector<int> loop;
      std::vector<Vector2d> uv;
      auto h = start;
      do {
        traced[std::size_t(h.idx())] = 1;
        const int o = out.from_vertex_handle(h).idx();
        const int canvasVertex = outToCanvas[std::size_t(o)];
        if (canvasVertex < 0) {
          throw StitchError(
              "the region reaches the edge of the target canvas: paint away from "
              "it or grow the target canvas");
        }
        loop.push_back(o);
        uv.push_back(target.uv[std::size_t(canvasVertex)]);
        h = out.next_halfedge_handle(h);
      } while (h != start);
      seams.push_back(std::move(loop));
      seamUv.push_back(std::move(uv));
    }
  }

  // The patch, after the target's vertices.
  const int patchBase = int(out.n_vertices());
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (auto v : patch.surface.vertices()) {
    const int c = patch.sourceVertex[std::size_t(v.idx())];
    const auto& g = draft.point(TriMesh::VertexHandle(c));
    if (offset && !offset->sample(source.uv[std::size_t(c)], shift)) {
      throw StitchError("the offset membrane is undefined at source canvas " + vertexText(c) +
                        " of the region");
    }
    out.add_vertex({g[0] + shift.x(), g[1] + shift.y(), g[2] + shift.z()});
  }
  result.patchVertices = patch.surface.n_vertices();
  for (auto f : patch.surface.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v : patch.surface.fv_range(f))
      corners.emplace_back(patchBase + v.idx());
    out.add_face(corners);
  }

  // Pair each boundary loop of R_in with the seam loop of the target nearest to it in the domain.
  const auto patchLoops = boundaryLoops(patch.surface);
  if (patchLoops.size() != seams.size()) {
    throw StitchError("the region has " + std::to_string(patchLoops.size()) +
                      " boundary loops on the source but " + std::to_string(seams.size()) +
                      " on the target: paint a region whose outline both canvases hold whole");
  }
  std::vector<char> paired(seams.size(), 0);
  for (const auto& loop : patchLoops) {
    std::vector<int> ids;
    std::vector<Vector2d> uv;
    for (int v : loop) {
      ids.push_back(patchBase + v);
      uv.push_back(source.uv[std::size_t(patch.sourceVertex[std::size_t(v)])]);
    }
    std::size_t best = seams.size();
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < seams.size(); ++s) {
      const double d = paired[s] ? bestDistance : meanNearestDistance(uv, seamUv[s]);
      if (d < bestDistance) {
        bestDistance = d;
        best = s;
      }
    }
    if (best == seams.size()) throw StitchError("two source loops pair with one seam loop");
    paired[best] = 1;
    for (const auto& t : zip(ids, uv, seams[best], seamUv[best])) {
      const auto face = out.add_face(TriMesh::VertexHandle(t[0]), TriMesh::VertexHandle(t[1]),
                                     TriMesh::VertexHandle(t[2]));
      if (!face.is_valid()) {
        throw StitchError("the seam strip folds onto itself near target canvas " +
                          vertexText(outToCanvas[std::size_t(t[2] < patchBase ? t[2] : t[0])]) +
                          ": the two outlines are too far apart or too jagged to join");
      }
      ++result.gapTriangles;
    }
    ++result.seamLoops;
  }
  return result;
}

}  // namespace geobrush
