#include "cut_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geobrush/border_loop.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

// The edge-connected components of the faces `kept` selects: a label per face (-1: not kept) and
// each label's face count, labels in order of each component's lowest face.
struct Components {
  std::vector<int> label;
  std::vector<std::size_t> size;
};

Components faceComponents(const TriMesh& mesh, const std::vector<char>& kept) {
  Components c;
  c.label.assign(mesh.n_faces(), -1);
  std::vector<int> queue;
  for (int start = 0; start < int(mesh.n_faces()); ++start) {
    if (!kept[std::size_t(start)] || c.label[std::size_t(start)] >= 0) continue;
    const int id = int(c.size.size());
    queue.assign(1, start);
    c.label[std::size_t(start)] = id;
    for (std::size_t next = 0; next < queue.size(); ++next)
      for (const auto g : mesh.ff_range(TriMesh::FaceHandle(queue[next])))
        if (kept[std::size_t(g.idx())] && c.label[std::size_t(g.idx())] < 0) {
          c.label[std::size_t(g.idx())] = id;
          queue.push_back(g.idx());
        }
    c.size.push_back(queue.size());
  }
  return c;
}

void requireOneManifoldComponent(const TriMesh& mesh) {
  if (mesh.n_faces() == 0) throw CutRegionError("mesh", "the mesh has no faces");
  std::vector<int> boundaryLeaving(mesh.n_vertices(), 0);
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h) && ++boundaryLeaving[std::size_t(mesh.from_vertex_handle(h).idx())] > 1)
      throw CutRegionError("mesh", "vertex " + std::to_string(mesh.from_vertex_handle(h).idx()) +
                                       " is not manifold (its faces form several fans)");
  const Components parts = faceComponents(mesh, std::vector<char>(mesh.n_faces(), 1));
  if (parts.size.size() > 1)
    throw CutRegionError("mesh", "the mesh has " + std::to_string(parts.size.size()) +
                                     " connected parts; a hole is cut from one (keep its "
                                     "largest part first)");
}

// Keeps the component with the most faces (ties: the one with the lowest face); whether any face
// was dropped.
bool keepLargestComponent(const TriMesh& mesh, std::vector<char>& kept) {
  const Components parts = faceComponents(mesh, kept);
  if (parts.size.size() < 2) return false;
  const int main = int(std::max_element(parts.size.begin(), parts.size.end()) - parts.size.begin());
  for (std::size_t f = 0; f < kept.size(); ++f)
    if (kept[f] && parts.label[f] != main) kept[f] = 0;
  return true;
}

// The runs of kept faces around `v` (its wedges), each in the order its outgoing halfedges turn.
std::vector<std::vector<int>> wedges(const TriMesh& mesh, TriMesh::VertexHandle v,
                                     const std::vector<char>& kept) {
  std::vector<int> ring;  // face per outgoing halfedge, -1 for a gap (boundary or removed)
  for (const auto h : mesh.voh_range(v)) {
    const auto f = mesh.face_handle(h);
    ring.push_back(f.is_valid() && kept[std::size_t(f.idx())] ? f.idx() : -1);
  }
  const auto gap = std::find(ring.begin(), ring.end(), -1);
  if (gap == ring.end()) return {ring};  // a closed fan of kept faces
  std::rotate(ring.begin(), gap, ring.end());
  std::vector<std::vector<int>> runs;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    if (ring[k] < 0) continue;
    if (k == 0 || ring[k - 1] < 0) runs.emplace_back();
    runs.back().push_back(ring[k]);
  }
  return runs;
}

// Where the kept faces around `v` form several wedges, removes all but the one with the most
// faces (ties: the one holding the lowest face); whether any face was removed.
bool keepLargestWedge(const TriMesh& mesh, TriMesh::VertexHandle v, std::vector<char>& kept) {
  const auto runs = wedges(mesh, v, kept);
  if (runs.size() < 2) return false;
  auto larger = [](const std::vector<int>& a, const std::vector<int>& b) {
    if (a.size() != b.size()) return a.size() > b.size();
    return *std::min_element(a.begin(), a.end()) < *std::min_element(b.begin(), b.end());
  };
  const auto best = std::min_element(runs.begin(), runs.end(), larger);
  for (auto run = runs.begin(); run != runs.end(); ++run)
    if (run != best)
      for (int f : *run)
        kept[std::size_t(f)] = 0;
  return true;
}

// One pass over the corners of removed faces in increasing order; whether any face was removed.
bool resolvePinches(const TriMesh& mesh, std::vector<char>& kept) {
  std::vector<char> touched(mesh.n_vertices(), 0);
  for (const auto f : mesh.faces())
    if (!kept[std::size_t(f.idx())])
      for (const auto v : mesh.fv_range(f))
        touched[std::size_t(v.idx())] = 1;
  bool changed = false;
  for (std::size_t v = 0; v < touched.size(); ++v)
    if (touched[v]) changed |= keepLargestWedge(mesh, TriMesh::VertexHandle(int(v)), kept);
  return changed;
}

// The faces left once the painted ones go and the rest is cleaned into one manifold piece.
std::vector<char> keptFaces(const TriMesh& mesh, const std::vector<char>& painted,
                            std::size_t& paintedFaces) {
  std::vector<char> kept(mesh.n_faces(), 1);
  paintedFaces = 0;
  for (const auto f : mesh.faces())
    for (const auto v : mesh.fv_range(f))
      if (painted[std::size_t(v.idx())] && kept[std::size_t(f.idx())]) {
        kept[std::size_t(f.idx())] = 0;
        ++paintedFaces;
      }
  if (paintedFaces == 0)
    throw CutRegionError("strokes", "the painted vertices have no faces: nothing to remove");
  bool changed = true;
  while (changed) {
    changed = keepLargestComponent(mesh, kept);
    changed |= resolvePinches(mesh, kept);
  }
  if (std::find(kept.begin(), kept.end(), 1) == kept.end())
    throw CutRegionError("strokes", "the painting covers the whole mesh: nothing would be left");
  return kept;
}

std::vector<int> facesWhere(const std::vector<char>& flags, char value) {
  std::vector<int> faces;
  for (std::size_t f = 0; f < flags.size(); ++f)
    if (flags[f] == value) faces.push_back(int(f));
  return faces;
}

// The loop the cut opened: the one boundary loop of `result.mesh` through vertices that lost
// faces, away from the input's own boundary.
std::vector<int> newBorder(const TriMesh& mesh, const std::vector<char>& kept,
                           const CutRegionResult& result) {
  auto lostFaces = [&](int out) {
    const auto v = TriMesh::VertexHandle(result.keptVertex[std::size_t(out)]);
    return std::any_of(mesh.cvf_begin(v), mesh.cvf_end(v),
                       [&](auto f) { return !kept[std::size_t(f.idx())]; });
  };
  std::vector<std::vector<int>> opened;
  for (auto& loop : boundaryLoops(result.mesh))
    if (std::any_of(loop.begin(), loop.end(), lostFaces)) opened.push_back(std::move(loop));
  if (opened.size() != 1)
    throw CutRegionError("strokes", "the cut opens " + std::to_string(opened.size()) +
                                        " boundary loops, not one (the painted region goes "
                                        "around a handle): paint one disc-like region");
  for (int out : opened.front()) {
    const int v = result.keptVertex[std::size_t(out)];
    if (mesh.is_boundary(TriMesh::VertexHandle(v)))
      throw CutRegionError("strokes",
                           "the painted region reaches the mesh's existing boundary at "
                           "vertex " +
                               std::to_string(v) + ": paint away from it, or over the whole hole");
  }
  return std::move(opened.front());
}

CutRegionResult cut(const TriMesh& mesh, const std::vector<char>& painted) {
  if (painted.size() != mesh.n_vertices())
    throw std::invalid_argument("the painting has " + std::to_string(painted.size()) +
                                " flags for " + std::to_string(mesh.n_vertices()) + " vertices");
  CutRegionResult result;
  result.paintedVertices =
      std::size_t(std::count_if(painted.begin(), painted.end(), [](char p) { return p != 0; }));
  if (result.paintedVertices == 0) throw CutRegionError("strokes", "no vertex is painted");
  const std::vector<char> kept = keptFaces(mesh, painted, result.paintedFaces);
  result.keptFace = facesWhere(kept, 1);
  result.removedFace = facesWhere(kept, 0);
  result.cleanedFaces = result.removedFace.size() - result.paintedFaces;
  result.keptVertex = appendFaces(result.mesh, mesh, result.keptFace).sourceVertex;
  result.removedVertex = appendFaces(result.removed, mesh, result.removedFace).sourceVertex;
  result.border = newBorder(mesh, kept, result);
  return result;
}

CutRegionResult existingHole(const TriMesh& mesh, const Eigen::Vector3d& near) {
  if (!near.allFinite()) throw CutRegionError("near", "every coordinate must be a finite number");
  auto loops = boundaryLoops(mesh);
  if (loops.empty())
    throw CutRegionError("mesh",
                         "the mesh has no hole to pick: it is closed (paint a region "
                         "to cut through the canvas and strokes inputs)");
  std::size_t best = 0;
  int bestVertex = std::numeric_limits<int>::max();
  double bestDistance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < loops.size(); ++i)
    for (int v : loops[i]) {
      const double d = (pointOf(mesh, v) - near).squaredNorm();
      if (d < bestDistance || (d == bestDistance && v < bestVertex)) {
        best = i;
        bestVertex = v;
        bestDistance = d;
      }
    }
  if (!std::isfinite(bestDistance))
    throw CutRegionError("mesh", "the mesh's boundary vertices have non-finite coordinates");
  CutRegionResult result;
  result.mesh = mesh;
  result.border = std::move(loops[best]);
  for (int v = 0; v < int(mesh.n_vertices()); ++v)
    result.keptVertex.push_back(v);
  for (int f = 0; f < int(mesh.n_faces()); ++f)
    result.keptFace.push_back(f);
  return result;
}

}  // namespace

Painting paintedVertices(const Mesh& mesh, const Parameterization& canvas, const Strokes& strokes) {
  if (!canvas.canvas || !canvas.canvas->source)
    throw CutRegionError("canvas", "the parameterization has no canvas on a mesh");
  const Canvas& c = *canvas.canvas;
  if (c.source.get() != &mesh && c.source->contentHash() != mesh.contentHash())
    throw CutRegionError("canvas", "the canvas lies on another mesh than the one on input 'mesh'");
  const std::size_t n = c.surface.n_vertices();
  if (canvas.uv.size() != n || c.sourceVertex.size() != n)
    throw CutRegionError("canvas", "the canvas has " + std::to_string(n) + " vertices but " +
                                       std::to_string(canvas.uv.size()) + " uv and " +
                                       std::to_string(c.sourceVertex.size()) + " source vertices");
  Painting p;
  p.painted.assign(mesh.surface.n_vertices(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int v = c.sourceVertex[i];
    if (v < 0 || v >= int(p.painted.size()))
      throw CutRegionError("canvas", "canvas vertex " + std::to_string(i) + " maps to vertex " +
                                         std::to_string(v) + ", which the mesh does not have");
    if (!strokes.contains(canvas.uv[i])) continue;
    p.count += !p.painted[std::size_t(v)];
    p.painted[std::size_t(v)] = 1;
  }
  if (p.count == 0) throw CutRegionError("strokes", "the strokes paint no vertex of the canvas");
  for (int b : c.boundary)
    if (b >= 0 && b < int(n) && p.painted[std::size_t(c.sourceVertex[std::size_t(b)])])
      p.reachesCanvasBorder = true;
  return p;
}

CutRegionResult cutRegion(const TriMesh& mesh, const CutRegionOptions& options) {
  requireOneManifoldComponent(mesh);
  return options.painted.empty() ? existingHole(mesh, options.near) : cut(mesh, options.painted);
}

}  // namespace geobrush
