#include "gap_fill.hpp"

#include <string>

#include "geobrush/cut_paste.hpp"
#include "geobrush/loop_zip.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {
namespace {

// The target's faces outside the region, copied with their connectivity.
AppendedFaces keepOutside(TriMesh& out, const TriMesh& target, const Canvas& region) {
  std::vector<char> removed(target.n_faces(), 0);
  for (int f : region.sourceFace)
    removed[std::size_t(f)] = 1;
  std::vector<int> kept;
  for (std::size_t f = 0; f < removed.size(); ++f)
    if (!removed[f]) kept.push_back(int(f));
  if (kept.empty()) throw std::invalid_argument("the region covers the whole target");
  return appendFaces(out, target, kept);
}

// The feature's vertices and faces after the target's; returns the feature vertex -> result map.
std::vector<int> appendFeature(TriMesh& out, const TriMesh& pasted) {
  std::vector<int> ids(pasted.n_vertices());
  for (auto v : pasted.vertices())
    ids[std::size_t(v.idx())] = out.add_vertex(pasted.point(v)).idx();
  for (auto f : pasted.faces()) {
    std::array<TriMesh::VertexHandle, 3> corners;
    int c = 0;
    for (auto v : pasted.fv_range(f))
      corners[std::size_t(c++)] = TriMesh::VertexHandle(ids[std::size_t(v.idx())]);
    if (!out.add_face(corners[0], corners[1], corners[2]).is_valid())
      throw std::invalid_argument("feature face " + std::to_string(f.idx()) + " cannot be added");
  }
  return ids;
}

struct Loops {
  std::vector<int> feature, hole;  // result vertex ids, in their boundary halfedges' direction
  std::vector<int> featureCanvas, holeCanvas;  // the same vertices on their canvases
};

Loops gapLoops(const Canvas& region, const Canvas& feature, const AppendedFaces& kept,
               const std::vector<int>& featureIds) {
  Loops loops;
  for (int v : feature.boundary) {
    loops.feature.push_back(featureIds[std::size_t(v)]);
    loops.featureCanvas.push_back(v);
  }
  // The hole runs against the region's own boundary.
  for (auto it = region.boundary.rbegin(); it != region.boundary.rend(); ++it) {
    const int id = kept.vertexInOut[std::size_t(region.sourceVertex[std::size_t(*it)])];
    if (id < 0) throw std::invalid_argument("the region's outline is not on the kept target");
    loops.hole.push_back(id);
    loops.holeCanvas.push_back(*it);
  }
  return loops;
}

std::vector<std::array<int, 3>> zipInSpace(const TriMesh& out, const Loops& loops) {
  const std::vector<Eigen::Vector3d> normals = vertexNormals(out);
  std::vector<Eigen::Vector3d> pa, pb, na, nb;
  for (int v : loops.feature) {
    pa.push_back(pointOf(out, v));
    na.push_back(normals[std::size_t(v)]);
  }
  for (int v : loops.hole) {
    pb.push_back(pointOf(out, v));
    nb.push_back(normals[std::size_t(v)]);
  }
  return zipLoops(loops.feature, loops.hole, SpaceZipMetric(pa, pb, na, nb), true);
}

std::vector<std::array<int, 3>> zipInDomain(const Loops& loops, const GapDomain& domain) {
  std::vector<Eigen::Vector2d> uvA, uvB;
  for (int v : loops.featureCanvas)
    uvA.push_back(domain.featureUv->at(std::size_t(v)));
  for (int v : loops.holeCanvas)
    uvB.push_back(domain.regionUv->at(std::size_t(v)));
  return zipLoops(loops.feature, loops.hole, DomainZipMetric(uvA, uvB), true);
}

std::vector<int> zipGap(TriMesh& out, const Loops& loops, const GapDomain& domain) {
  const bool inDomain = domain.regionUv && domain.featureUv;
  std::vector<int> faces;
  for (const auto& t : inDomain ? zipInDomain(loops, domain) : zipInSpace(out, loops)) {
    const auto f = out.add_face(TriMesh::VertexHandle(t[0]), TriMesh::VertexHandle(t[1]),
                                TriMesh::VertexHandle(t[2]));
    if (!f.is_valid())
      throw std::invalid_argument("the gap's triangle " + std::to_string(t[0]) + ", " +
                                  std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                                  " would make the result non-manifold");
    faces.push_back(f.idx());
  }
  return faces;
}

// Ring 0 is the gap's vertices; pass k smooths rings 0..k-1 (the paper's widening passes).
void smoothRings(TriMesh& out, const Loops& loops, int passes) {
  std::vector<char> movable(out.n_vertices(), 0);
  std::vector<int> ring;
  for (const auto* loop : {&loops.feature, &loops.hole})
    for (int v : *loop)
      if (!movable[std::size_t(v)]) {
        movable[std::size_t(v)] = 1;
        ring.push_back(v);
      }
  for (int pass = 1; pass <= passes; ++pass) {
    if (pass > 1) {
      std::vector<int> next;
      for (int v : ring)
        for (auto w : out.vv_range(TriMesh::VertexHandle(v)))
          if (!movable[std::size_t(w.idx())] && !out.is_boundary(w)) {
            movable[std::size_t(w.idx())] = 1;
            next.push_back(w.idx());
          }
      ring = std::move(next);
    }
    umbrellaSmooth(out, movable, 1);
  }
}

}  // namespace

GapFillResult fillGap(const TriMesh& target, const Canvas& region, const TriMesh& pasted,
                      const Canvas& feature, const GapFillOptions& options,
                      const GapDomain& domain) {
  if (pasted.n_vertices() != feature.surface.n_vertices() ||
      pasted.n_faces() != feature.surface.n_faces())
    throw std::invalid_argument("the pasted mesh does not have the feature's connectivity");
  GapFillResult result;
  const AppendedFaces kept = keepOutside(result.mesh, target, region);
  const std::size_t keptVertices = result.mesh.n_vertices();
  const std::vector<int> featureIds = appendFeature(result.mesh, pasted);
  const Loops loops = gapLoops(region, feature, kept, featureIds);
  result.map.seamFaces = zipGap(result.mesh, loops, domain);
  smoothRings(result.mesh, loops, options.smoothIterations);

  result.map.targetVertex.assign(result.mesh.n_vertices(), -1);
  result.map.sourceVertex.assign(result.mesh.n_vertices(), -1);
  for (std::size_t v = 0; v < keptVertices; ++v)
    result.map.targetVertex[v] = kept.sourceVertex[v];
  for (std::size_t i = 0; i < featureIds.size(); ++i)
    result.map.sourceVertex[std::size_t(featureIds[i])] = int(i);
  return result;
}

}  // namespace geobrush
