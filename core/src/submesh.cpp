#include "geobrush/submesh.hpp"

#include <algorithm>
#include <array>
#include <atomic>

#include "append_faces.hpp"
#include "geobrush/parallel.hpp"

namespace geobrush {

namespace {

// The submesh's connectivity set directly, as add_face would link the faces one by one: new edges
// in the order the faces first use them, each halfedge 2e running the way its first face runs it,
// a face's halfedge the one into its first corner, a boundary vertex's halfedge its boundary
// halfedge and an inner vertex's its halfedge in the last face around it (which closed its fan).
// That link is unique only where the faces form one fan at every vertex: returns false, leaving
// `sub.surface` empty, where they do not. `corner` holds the faces' corners, `local` maps mesh
// vertices to submesh vertices; costs the region's size, but for a mark per mesh edge.
bool linkManifold(const TriMesh& mesh, const std::vector<int>& faces,
                  const std::vector<int>& corner, const std::vector<int>& local, Submesh& sub) {
  using HalfedgeHandle = TriMesh::HalfedgeHandle;
  const std::size_t nv = sub.sourceVertex.size(), nf = faces.size();
  std::vector<int> edgeOf(mesh.n_edges(), -1);  // mesh edge -> submesh edge
  std::vector<int> firstHalfedge;               // submesh edge -> the mesh halfedge that made it
  std::vector<int> faceHalfedge(3 * nf);        // face k's halfedge out of corner i: 3k + i
  for (std::size_t k = 0; k < nf; ++k) {
    const int* c = corner.data() + 3 * k;
    std::array<HalfedgeHandle, 3> around;  // by the corner it leaves
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(faces[k]))) {
      const int from = mesh.from_vertex_handle(h).idx();
      around[from == c[0] ? 0 : from == c[1] ? 1 : 2] = h;
    }
    for (std::size_t i = 0; i < 3; ++i) {
      const int h = around[i].idx();
      int& e = edgeOf[std::size_t(h / 2)];
      if (e < 0) {
        e = int(firstHalfedge.size());
        firstHalfedge.push_back(h);
      }
      // The edge's halfedge 2e runs the way the face that made it runs it.
      faceHalfedge[3 * k + i] = 2 * e + (h != firstHalfedge[std::size_t(e)]);
    }
  }
  std::vector<int> halfedgeFace(2 * firstHalfedge.size(), -1);
  std::vector<int> halfedgeTo(2 * firstHalfedge.size(), -1);
  for (std::size_t k = 0; k < nf; ++k)
    for (int i = 0; i < 3; ++i) {
      const int h = faceHalfedge[3 * k + std::size_t(i)];
      halfedgeFace[std::size_t(h)] = int(k);
      halfedgeTo[std::size_t(h)] = local[std::size_t(corner[3 * k + std::size_t((i + 1) % 3)])];
      halfedgeTo[std::size_t(h ^ 1)] = local[std::size_t(corner[3 * k + std::size_t(i)])];
    }
  std::vector<int> boundaryOut(nv, -1), lastOut(nv, -1);
  for (std::size_t h = 0; h < halfedgeFace.size(); ++h) {
    if (halfedgeFace[h] >= 0) continue;
    const int from = halfedgeTo[h ^ 1];
    if (boundaryOut[std::size_t(from)] >= 0) return false;  // a second fan
    boundaryOut[std::size_t(from)] = int(h);
  }
  for (std::size_t k = 0; k < nf; ++k)
    for (int i = 0; i < 3; ++i)
      lastOut[std::size_t(local[std::size_t(corner[3 * k + std::size_t(i)])])] =
          faceHalfedge[3 * k + std::size_t(i)];

  TriMesh& out = sub.surface;
  out.resize(nv, firstHalfedge.size(), nf);
  for (std::size_t v = 0; v < nv; ++v) {
    const auto vh = TriMesh::VertexHandle(int(v));
    out.set_point(vh, mesh.point(TriMesh::VertexHandle(sub.sourceVertex[v])));
    out.set_halfedge_handle(vh, HalfedgeHandle(boundaryOut[v] >= 0 ? boundaryOut[v] : lastOut[v]));
  }
  for (std::size_t h = 0; h < halfedgeFace.size(); ++h) {
    out.set_vertex_handle(HalfedgeHandle(int(h)), TriMesh::VertexHandle(halfedgeTo[h]));
    if (halfedgeFace[h] < 0) {
      out.set_face_handle(HalfedgeHandle(int(h)), TriMesh::FaceHandle());
      out.set_next_halfedge_handle(HalfedgeHandle(int(h)),
                                   HalfedgeHandle(boundaryOut[std::size_t(halfedgeTo[h])]));
    }
  }
  for (std::size_t k = 0; k < nf; ++k) {
    const auto fh = TriMesh::FaceHandle(int(k));
    const int* h = faceHalfedge.data() + 3 * k;
    out.set_halfedge_handle(fh, HalfedgeHandle(h[2]));
    for (int i = 0; i < 3; ++i) {
      out.set_face_handle(HalfedgeHandle(h[i]), fh);
      out.set_next_halfedge_handle(HalfedgeHandle(h[i]), HalfedgeHandle(h[(i + 1) % 3]));
    }
  }
  return true;
}

}  // namespace

Submesh extractSubmesh(const TriMesh& mesh, const std::vector<int>& faces) {
  Submesh sub;
  std::vector<int> corner;
  corner.reserve(3 * faces.size());
  for (int f : faces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      corner.push_back(v.idx());
  // Deduplicating through a mark per mesh vertex leaves only the region's vertices to sort.
  std::vector<int> local(mesh.n_vertices(), -1);
  for (int v : corner)
    if (local[std::size_t(v)] < 0) {
      local[std::size_t(v)] = 0;
      sub.sourceVertex.push_back(v);
    }
  std::sort(sub.sourceVertex.begin(), sub.sourceVertex.end());
  for (std::size_t i = 0; i < sub.sourceVertex.size(); ++i)
    local[std::size_t(sub.sourceVertex[i])] = int(i);
  sub.sourceFace = faces;
  if (linkManifold(mesh, faces, corner, local, sub)) return sub;

  // Several fans at a vertex: add_face, face by face, links them where it can.
  sub.sourceFace.clear();
  sub.surface.reserve(sub.sourceVertex.size(), sub.sourceVertex.size() + faces.size(),
                      faces.size());
  for (int v : sub.sourceVertex)
    sub.surface.add_vertex(mesh.point(TriMesh::VertexHandle(v)));
  sub.sourceFace.reserve(faces.size());
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int* c = corner.data() + 3 * k;
    const auto added = sub.surface.add_face(TriMesh::VertexHandle(local[std::size_t(c[0])]),
                                            TriMesh::VertexHandle(local[std::size_t(c[1])]),
                                            TriMesh::VertexHandle(local[std::size_t(c[2])]));
    if (!added.is_valid()) {
      sub.unattachedFace = faces[k];
      break;
    }
    sub.sourceFace.push_back(faces[k]);
  }
  return sub;
}

}  // namespace geobrush

namespace geobrush {

AppendedFaces appendFaces(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces) {
  return appendFacesReusing(out, mesh, faces, {});
}

AppendedFaces appendFacesReusing(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces,
                                 AppendedFaces storage) {
  using HalfedgeHandle = TriMesh::HalfedgeHandle;
  // Every pass walks the mesh's arrays in order, split into blocks over the cores; each item is
  // written by one block alone, so the copy is the same for any number of threads.
  constexpr std::size_t kBlock = 1 << 14;
  AppendedFaces added = std::move(storage);
  added.sourceVertex.clear();
  added.firstVertex = int(out.n_vertices());
  const int firstEdge = int(out.n_edges()), firstFace = int(out.n_faces());

  // New indices: faces in the given order, edges and vertices in source order.
  std::vector<int>& faceInOut = added.faceInOut;
  faceInOut.assign(mesh.n_faces(), -1);
  for (std::size_t k = 0; k < faces.size(); ++k)
    faceInOut[std::size_t(faces[k])] = firstFace + int(k);
  auto selected = [&](HalfedgeHandle h) {
    const auto f = mesh.face_handle(h);
    return f.is_valid() && faceInOut[std::size_t(f.idx())] >= 0;
  };
  std::vector<int>& edgeInOut = added.edgeInOut;
  edgeInOut.assign(mesh.n_edges(), -1);
  std::vector<char> used(mesh.n_vertices(), 0);
  // The edges and vertices of the faces: marked from the faces where they are few, else by a walk
  // over the mesh's edges, split over the cores. Either marks the same.
  if (faces.size() * 8 < mesh.n_faces()) {
    for (int f : faces)
      for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
        edgeInOut[std::size_t(h.idx() / 2)] = 0;
        used[std::size_t(mesh.to_vertex_handle(h).idx())] = 1;
      }
  } else {
    parallelBlocks(mesh.n_edges(), kBlock, 0, [&](std::size_t first, std::size_t last) {
      for (std::size_t e = first; e < last; ++e) {
        const auto h = HalfedgeHandle(int(2 * e)), o = HalfedgeHandle(int(2 * e + 1));
        if (!selected(h) && !selected(o)) continue;
        edgeInOut[e] = 0;
        // Several edges mark one vertex, with the same value.
        std::atomic_ref(used[std::size_t(mesh.to_vertex_handle(h).idx())])
            .store(1, std::memory_order_relaxed);
        std::atomic_ref(used[std::size_t(mesh.to_vertex_handle(o).idx())])
            .store(1, std::memory_order_relaxed);
      }
    });
  }
  int edges = 0;
  for (int& e : edgeInOut)
    if (e == 0) e = firstEdge + edges++;
  added.vertexInOut.assign(mesh.n_vertices(), -1);
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      added.vertexInOut[v] = added.firstVertex + int(added.sourceVertex.size());
      added.sourceVertex.push_back(int(v));
    }
  out.resize(out.n_vertices() + added.sourceVertex.size(), out.n_edges() + std::size_t(edges),
             out.n_faces() + faces.size());

  // Halfedge 2e + s is side s of edge e, in OpenMesh as here.
  auto halfedgeInOut = [&](HalfedgeHandle h) {
    return HalfedgeHandle(2 * edgeInOut[std::size_t(h.idx() / 2)] + (h.idx() & 1));
  };
  parallelBlocks(added.sourceVertex.size(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const auto v = TriMesh::VertexHandle(added.sourceVertex[i]);
      const auto vOut = TriMesh::VertexHandle(added.firstVertex + int(i));
      out.set_point(vOut, mesh.point(v));
      // Inside the selection any outgoing halfedge will do; boundary vertices get theirs below.
      const auto h = mesh.halfedge_handle(v);
      if (edgeInOut[std::size_t(h.idx() / 2)] >= 0) out.set_halfedge_handle(vOut, halfedgeInOut(h));
    }
  });
  parallelBlocks(faces.size(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k)
      out.set_halfedge_handle(TriMesh::FaceHandle(firstFace + int(k)),
                              halfedgeInOut(mesh.halfedge_handle(TriMesh::FaceHandle(faces[k]))));
  });
  const std::size_t blocks = (mesh.n_halfedges() + kBlock - 1) / kBlock;
  std::vector<std::vector<HalfedgeHandle>> boundaryOfBlock(blocks);
  parallelBlocks(mesh.n_halfedges(), kBlock, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const auto h = HalfedgeHandle(int(i));
      if (edgeInOut[i / 2] < 0) continue;
      const auto hOut = halfedgeInOut(h);
      const auto to = mesh.to_vertex_handle(h);
      out.set_vertex_handle(hOut, TriMesh::VertexHandle(added.vertexInOut[std::size_t(to.idx())]));
      if (selected(h)) {
        out.set_face_handle(hOut,
                            TriMesh::FaceHandle(faceInOut[std::size_t(mesh.face_handle(h).idx())]));
        // Each halfedge is the next of one other: the prev this also sets has one writer.
        out.set_next_halfedge_handle(hOut, halfedgeInOut(mesh.next_halfedge_handle(h)));
        continue;
      }
      // A boundary halfedge of the copy: its successor is the first boundary halfedge leaving
      // `to` clockwise, past the faces not copied. With one fan at `to` that is the fan's other
      // end; with several it joins them as add_face does, so that circulators see every fan.
      out.set_face_handle(hOut, TriMesh::FaceHandle());
      auto next = mesh.opposite_halfedge_handle(h);
      do
        next = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(next));
      while (selected(next) || !selected(mesh.opposite_halfedge_handle(next)));
      out.set_next_halfedge_handle(hOut, halfedgeInOut(next));
      boundaryOfBlock[i / kBlock].push_back(hOut);
    }
  });
  // OpenMesh expects a boundary vertex to hold a boundary halfedge; where a vertex has several,
  // the last in source order, as a sequential pass would leave it.
  for (const auto& boundary : boundaryOfBlock)
    for (auto hOut : boundary)
      out.set_halfedge_handle(out.from_vertex_handle(hOut), hOut);
  return added;
}

AppendedFaces joinFaces(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces,
                        AppendedFaces joined) {
  using HalfedgeHandle = TriMesh::HalfedgeHandle;
  using VertexHandle = TriMesh::VertexHandle;
  AppendedFaces added;
  added.firstVertex = int(out.n_vertices());
  added.vertexInOut = std::move(joined.vertexInOut);
  added.edgeInOut = std::move(joined.edgeInOut);
  added.faceInOut = std::move(joined.faceInOut);
  const int firstFace = int(out.n_faces());
  for (std::size_t k = 0; k < faces.size(); ++k)
    added.faceInOut[std::size_t(faces[k])] = firstFace + int(k);
  auto selected = [&](HalfedgeHandle h) {
    const auto f = mesh.face_handle(h);
    return f.is_valid() && added.faceInOut[std::size_t(f.idx())] >= 0;
  };

  // The new edges and vertices in the order the new faces first use them, and every vertex the
  // new faces reach.
  std::vector<int> newEdges, newVertices, reached;
  std::vector<char> isReached(mesh.n_vertices(), 0);
  for (int f : faces)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(f))) {
      int& e = added.edgeInOut[std::size_t(h.idx() / 2)];
      if (e < 0) {
        e = int(out.n_edges() + newEdges.size());
        newEdges.push_back(h.idx() / 2);
      }
      const int v = mesh.to_vertex_handle(h).idx();
      if (isReached[std::size_t(v)]) continue;
      isReached[std::size_t(v)] = 1;
      reached.push_back(v);
      int& vOut = added.vertexInOut[std::size_t(v)];
      if (vOut < 0) {
        vOut = added.firstVertex + int(newVertices.size());
        newVertices.push_back(v);
      }
    }
  added.sourceVertex = newVertices;
  out.resize(out.n_vertices() + newVertices.size(), out.n_edges() + newEdges.size(),
             out.n_faces() + faces.size());

  auto halfedgeInOut = [&](HalfedgeHandle h) {
    return HalfedgeHandle(2 * added.edgeInOut[std::size_t(h.idx() / 2)] + (h.idx() & 1));
  };
  auto vertexInOut = [&](VertexHandle v) {
    return VertexHandle(added.vertexInOut[std::size_t(v.idx())]);
  };
  // A boundary halfedge's successor, as appendFaces finds it.
  auto boundaryNext = [&](HalfedgeHandle h) {
    auto next = mesh.opposite_halfedge_handle(h);
    do
      next = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(next));
    while (selected(next) || !selected(mesh.opposite_halfedge_handle(next)));
    return halfedgeInOut(next);
  };
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const auto f = TriMesh::FaceHandle(faces[k]);
    out.set_halfedge_handle(TriMesh::FaceHandle(firstFace + int(k)),
                            halfedgeInOut(mesh.halfedge_handle(f)));
    // The new faces' own halfedges, on new and on shared edges alike.
    for (auto h : mesh.fh_range(f)) {
      const auto hOut = halfedgeInOut(h);
      out.set_vertex_handle(hOut, vertexInOut(mesh.to_vertex_handle(h)));
      out.set_face_handle(hOut, TriMesh::FaceHandle(firstFace + int(k)));
      out.set_next_halfedge_handle(hOut, halfedgeInOut(mesh.next_halfedge_handle(h)));
    }
  }
  // The other side of each new edge: a face of `joined` or of this call (set above), or the
  // boundary, which gets its successor anew and, where it is the only one leaving a new vertex,
  // becomes that vertex's halfedge.
  std::vector<int> boundaryLeaving(newVertices.size(), 0);  // per new vertex
  std::vector<HalfedgeHandle> vertexBoundary(newVertices.size());
  for (int e : newEdges)
    for (int side = 0; side < 2; ++side) {
      const auto h = mesh.halfedge_handle(TriMesh::EdgeHandle(e), side);
      if (selected(h)) continue;
      const auto hOut = halfedgeInOut(h);
      out.set_vertex_handle(hOut, vertexInOut(mesh.to_vertex_handle(h)));
      out.set_face_handle(hOut, TriMesh::FaceHandle());
      const int from = vertexInOut(mesh.from_vertex_handle(h)).idx() - added.firstVertex;
      if (from >= 0) {
        ++boundaryLeaving[std::size_t(from)];
        vertexBoundary[std::size_t(from)] = hOut;
      }
    }
  for (int e : newEdges)
    for (int side = 0; side < 2; ++side) {
      const auto h = mesh.halfedge_handle(TriMesh::EdgeHandle(e), side);
      if (!selected(h)) out.set_next_halfedge_handle(halfedgeInOut(h), boundaryNext(h));
    }
  // Vertices hold a boundary halfedge where they have one. A new vertex with none is inside the
  // copy, where mesh's own halfedge will do (the first the circulation below would find); one
  // with a single boundary halfedge leaving it has it. Vertices `joined` had, and new ones where
  // several fans meet, are circulated: every boundary halfedge that ends there gets its
  // successor anew (the faces may have closed the gap it led into), and the vertex the last
  // boundary halfedge leaving it.
  for (int v : reached) {
    const auto vh = VertexHandle(v);
    const int index = vertexInOut(vh).idx() - added.firstVertex;
    if (index >= 0 && boundaryLeaving[std::size_t(index)] < 2) {
      out.set_halfedge_handle(vertexInOut(vh), boundaryLeaving[std::size_t(index)] == 1
                                                   ? vertexBoundary[std::size_t(index)]
                                                   : halfedgeInOut(mesh.halfedge_handle(vh)));
      continue;
    }
    HalfedgeHandle outgoing, boundary;
    for (auto h : mesh.voh_range(vh)) {
      if (added.edgeInOut[std::size_t(h.idx() / 2)] < 0) continue;
      const auto incoming = mesh.opposite_halfedge_handle(h);
      if (!selected(incoming))
        out.set_next_halfedge_handle(halfedgeInOut(incoming), boundaryNext(incoming));
      if (!outgoing.is_valid()) outgoing = halfedgeInOut(h);
      if (!selected(h)) boundary = halfedgeInOut(h);
    }
    out.set_halfedge_handle(vertexInOut(vh), boundary.is_valid() ? boundary : outgoing);
  }
  for (std::size_t i = 0; i < newVertices.size(); ++i)
    out.set_point(VertexHandle(added.firstVertex + int(i)),
                  mesh.point(VertexHandle(newVertices[i])));
  return added;
}

}  // namespace geobrush
