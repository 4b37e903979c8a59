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
// A pinched vertex is a corner of a selected and of an unselected face: `candidates` lists faces
// whose corners include every such vertex (e.g. the smaller of the two sets), so that the cost
// follows the region rather than the mesh.
void removePinches(const TriMesh& mesh, std::vector<char>& selected,
                   const std::vector<int>& candidateFaces) {
  std::vector<int> candidates;
  for (int f : candidateFaces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
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
  const TriMesh& mesh = canvas.source ? canvas.source->surface : canvas.surface;
  StitchBase base;
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
  base.meshToCanvas.assign(mesh.n_vertices(), -1);
  for (std::size_t c = 0; c < base.canvasToMesh.size(); ++c) {
    const int v = base.canvasToMesh[c];
    if (v < 0 || std::size_t(v) >= mesh.n_vertices())
      throw StitchError("the target canvas maps a vertex outside the target mesh");
    base.meshToCanvas[std::size_t(v)] = int(c);
  }
  std::vector<char> inCanvas(mesh.n_faces(), 0);
  for (int f : base.canvasFaceToMesh) {
    if (f < 0 || std::size_t(f) >= mesh.n_faces())
      throw StitchError("the target canvas maps a face outside the target mesh");
    inCanvas[std::size_t(f)] = 1;
  }
  std::vector<int> outsideFaces;
  for (std::size_t f = 0; f < inCanvas.size(); ++f)
    (inCanvas[f] ? base.canvasMeshFaces : outsideFaces).push_back(int(f));
  base.outsideFaces = appendFaces(base.outside, mesh, outsideFaces);
  return base;
}

StitchResult stitchPaste(const Region2D& region, const Parameterization& source,
                         const TriMesh& draft, const Field2D* offset,
                         const Parameterization& target, const StitchBase* base) {
  StitchResult result;
  StitchResult made = stitchPasteInto(result.mesh, region, source, draft, offset, target, base);
  result.patchVertices = made.patchVertices;
  result.removedFaces = made.removedFaces;
  result.gapTriangles = made.gapTriangles;
  result.seamLoops = made.seamLoops;
  result.map = std::move(made.map);
  return result;
}

namespace {

// Room for the whole target, the source canvas and the seam strips: a paste never outgrows it.
void reserveForPaste(TriMesh& out, const TriMesh& targetMesh, const TriMesh& sourceCanvas,
                     std::size_t targetCanvasVertices) {
  const std::size_t strips = 2 * targetCanvasVertices / 8 + 1024;
  out.reserve(targetMesh.n_vertices() + sourceCanvas.n_vertices(),
              targetMesh.n_edges() + sourceCanvas.n_edges() + strips,
              targetMesh.n_faces() + sourceCanvas.n_faces() + strips);
}

}  // namespace

void copyOutside(const StitchBase& base, const TriMesh& targetMesh, const TriMesh& sourceCanvas,
                 TriMesh& out) {
  // Reserved first, the copy keeps the room (OpenMesh copies into the arrays it has).
  out.clear();
  reserveForPaste(out, targetMesh, sourceCanvas, base.canvasToMesh.size());
  out = base.outside;
}

StitchResult stitchPasteInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                             const TriMesh& draft, const Field2D* offset,
                             const Parameterization& target, const StitchBase* base,
                             bool outHoldsOutside) {
  if (outHoldsOutside && (!base || out.n_vertices() != base->outside.n_vertices() ||
                          out.n_faces() != base->outside.n_faces()))
    throw StitchError("the mesh to build into does not hold the target's outside part");
  if (!outHoldsOutside) out.clear();
  if (!source.canvas || !target.canvas) throw StitchError("the parameterizations have no canvases");
  const TriMesh& canvas = source.canvas->surface;
  if (draft.n_vertices() != canvas.n_vertices() || draft.n_faces() != canvas.n_faces())
    throw StitchError("the draft does not have the source canvas' vertices and faces");
  const TriMesh& targetMesh =
      target.canvas->source ? target.canvas->source->surface : target.canvas->surface;
  StitchResult result;  // its mesh stays empty: the mesh is `out`
  auto keepTarget = [&] {
    out = targetMesh;
    result.map.targetVertex.resize(targetMesh.n_vertices());
    std::iota(result.map.targetVertex.begin(), result.map.targetVertex.end(), 0);
    result.map.sourceVertex.assign(targetMesh.n_vertices(), -1);
  };
  if (region.empty()) {
    keepTarget();
    return result;
  }

  // R_in: the source faces with every corner in the region, made manifold.
  std::vector<char> inRegion(canvas.n_vertices(), 0);
  for (int v : region.sourceVertices)
    inRegion[std::size_t(v)] = 1;
  std::vector<char> patchSelected(canvas.n_faces(), 0);
  for (int v : region.sourceVertices)
    for (auto f : canvas.vf_range(TriMesh::VertexHandle(v))) {
      bool all = true;
      for (auto corner : canvas.fv_range(f))
        all = all && inRegion[std::size_t(corner.idx())];
      patchSelected[std::size_t(f.idx())] = all;
    }
  removePinches(canvas, patchSelected, selectedFaces(patchSelected));
  const std::vector<int> patchFaces = selectedFaces(patchSelected);
  if (patchFaces.empty()) {
    keepTarget();
    return result;
  }

  // The target: every face but those of its canvas that touch a covered vertex, made manifold.
  std::optional<StitchBase> ownBase;
  if (!base) base = &ownBase.emplace(stitchBase(target));
  const TriMesh& targetCanvas = target.canvas->surface;
  std::vector<char> outerBoundary(targetCanvas.n_vertices(), 0);
  for (int v : target.canvas->boundary)
    outerBoundary[std::size_t(v)] = 1;
  std::vector<char> covered(targetCanvas.n_vertices(), 0);
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
  std::vector<char> kept(targetMesh.n_faces(), 1);
  std::vector<int> removedFaces;
  for (int v : region.targetVertices)
    for (auto f : targetCanvas.vf_range(TriMesh::VertexHandle(v))) {
      char& k = kept[std::size_t(base->canvasFaceToMesh[std::size_t(f.idx())])];
      if (k) removedFaces.push_back(base->canvasFaceToMesh[std::size_t(f.idx())]);
      k = 0;
    }
  removePinches(targetMesh, kept, removedFaces);
  // The kept target faces, then the patch, their connectivity copied (add_face, face by face,
  // takes several times longer on a large target); room for the seam strips too. The part
  // outside the canvas is copied whole from the base, unless pinches reached it.
  auto reserve = [&] { reserveForPaste(out, targetMesh, canvas, targetCanvas.n_vertices()); };
  std::vector<int> keptFaces;
  removedFaces.clear();
  for (int f : base->canvasMeshFaces)
    (kept[std::size_t(f)] ? keptFaces : removedFaces).push_back(f);
  AppendedFaces targetPart;
  std::vector<int> outToMesh;  // vertex of `out` -> target mesh vertex
  if (std::size_t(std::count(kept.begin(), kept.end(), 0)) == removedFaces.size()) {
    if (!outHoldsOutside) {
      // Reserved first, the copy keeps the room (OpenMesh copies into the arrays it has).
      reserve();
      out = base->outside;
    }
    targetPart = joinFaces(out, targetMesh, keptFaces, base->outsideFaces);
    outToMesh = base->outsideFaces.sourceVertex;
  } else {
    keptFaces.clear();
    removedFaces.clear();
    for (std::size_t f = 0; f < kept.size(); ++f)
      (kept[f] ? keptFaces : removedFaces).push_back(int(f));
    out.clear();
    reserve();
    targetPart = appendFaces(out, targetMesh, keptFaces);
  }
  outToMesh.insert(outToMesh.end(), targetPart.sourceVertex.begin(), targetPart.sourceVertex.end());
  result.removedFaces = removedFaces.size();

  // The seam loops: boundary loops of the target part through a vertex of a removed face, found
  // before the patch is added.
  std::vector<std::vector<int>> seams;
  std::vector<std::vector<Vector2d>> seamUv;
  std::vector<char> traced(out.n_halfedges(), 0);
  for (int f : removedFaces)
    for (auto corner : targetMesh.fv_range(TriMesh::FaceHandle(f))) {
      const int o = targetPart.vertexInOut[std::size_t(corner.idx())];
      if (o < 0 || !out.is_boundary(TriMesh::VertexHandle(o))) continue;
      for (auto start : out.voh_range(TriMesh::VertexHandle(o))) {
        if (!out.is_boundary(start) || traced[std::size_t(start.idx())]) continue;
        std::vector<int> loop;
        std::vector<Vector2d> uv;
        auto h = start;
        do {
          traced[std::size_t(h.idx())] = 1;
          const int v = out.from_vertex_handle(h).idx();
          const int canvasVertex = base->meshToCanvas[std::size_t(outToMesh[std::size_t(v)])];
          if (canvasVertex < 0) {
            throw StitchError(
                "the region reaches the edge of the target canvas: paint away from "
                "it or grow the target canvas");
          }
          loop.push_back(v);
          uv.push_back(target.uv[std::size_t(canvasVertex)]);
          h = out.next_halfedge_handle(h);
        } while (h != start);
        seams.push_back(std::move(loop));
        seamUv.push_back(std::move(uv));
      }
    }

  // The patch, after the target's vertices, each vertex at x~(E_s(v)) + G(v).
  // Joined to nothing: the copy costs the region's size, not the canvas'.
  AppendedFaces nothing;
  nothing.vertexInOut.assign(canvas.n_vertices(), -1);
  nothing.edgeInOut.assign(canvas.n_edges(), -1);
  nothing.faceInOut.assign(canvas.n_faces(), -1);
  const AppendedFaces patch = joinFaces(out, canvas, patchFaces, nothing);
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < patch.sourceVertex.size(); ++i) {
    const int c = patch.sourceVertex[i];
    const auto& g = draft.point(TriMesh::VertexHandle(c));
    if (offset && !offset->sample(source.uv[std::size_t(c)], shift)) {
      throw StitchError("the offset membrane is undefined at source canvas " + vertexText(c) +
                        " of the region");
    }
    out.set_point(TriMesh::VertexHandle(patch.firstVertex + int(i)),
                  {g[0] + shift.x(), g[1] + shift.y(), g[2] + shift.z()});
  }
  result.patchVertices = patch.sourceVertex.size();
  std::vector<std::vector<int>> patchLoops;
  traced.assign(out.n_halfedges(), 0);
  for (int v = patch.firstVertex; v < int(out.n_vertices()); ++v) {
    if (!out.is_boundary(TriMesh::VertexHandle(v))) continue;
    for (auto start : out.voh_range(TriMesh::VertexHandle(v))) {
      if (!out.is_boundary(start) || traced[std::size_t(start.idx())]) continue;
      std::vector<int> loop;
      auto h = start;
      do {
        traced[std::size_t(h.idx())] = 1;
        loop.push_back(out.from_vertex_handle(h).idx());
        h = out.next_halfedge_handle(h);
      } while (h != start);
      patchLoops.push_back(std::move(loop));
    }
  }

  // Pair each boundary loop of R_in with the seam loop of the target nearest to it in the domain.
  if (patchLoops.size() != seams.size()) {
    throw StitchError("the region has " + std::to_string(patchLoops.size()) +
                      " boundary loops on the source but " + std::to_string(seams.size()) +
                      " on the target: paint a region whose outline both canvases hold whole");
  }
  std::vector<char> paired(seams.size(), 0);
  const int firstSeamFace = int(out.n_faces());
  for (const auto& ids : patchLoops) {
    std::vector<Vector2d> uv;
    for (int v : ids)
      uv.push_back(source.uv[std::size_t(patch.sourceVertex[std::size_t(v - patch.firstVertex)])]);
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
        throw StitchError(
            "the seam strip folds onto itself near target " +
            vertexText(outToMesh[std::size_t(t[2] < patch.firstVertex ? t[2] : t[0])]) +
            ": the two outlines are too far apart or too jagged to join");
      }
      ++result.gapTriangles;
    }
    ++result.seamLoops;
  }
  PasteMap& map = result.map;
  map.targetVertex = outToMesh;
  map.targetVertex.resize(out.n_vertices(), -1);
  map.sourceVertex.assign(std::size_t(patch.firstVertex), -1);
  map.sourceVertex.insert(map.sourceVertex.end(), patch.sourceVertex.begin(),
                          patch.sourceVertex.end());
  map.seamFaces.resize(out.n_faces() - std::size_t(firstSeamFace));
  std::iota(map.seamFaces.begin(), map.seamFaces.end(), firstSeamFace);
  return result;
}

}  // namespace geobrush
