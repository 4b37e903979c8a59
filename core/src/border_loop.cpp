#include "geobrush/border_loop.hpp"

#include <algorithm>

#include "geobrush/hash.hpp"
#include "geobrush/point_pairs.hpp"

namespace geobrush {

Hash BorderLoop::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(mesh ? mesh->contentHash() : 0);
  hasher.span(std::span<const int>(vertex));
  return hasher.digest();
}

std::string BorderLoop::summary() const {
  return "border loop of " + std::to_string(vertex.size()) + " vertices";
}

Hash PointPairs::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(border.size());
  for (const auto& b : border)
    hasher.f64(b.x()).f64(b.y()).f64(b.z());
  hasher.span(std::span<const int>(templateVertex));
  return hasher.digest();
}

std::string PointPairs::summary() const {
  return std::to_string(border.size()) + " point pairs";
}

namespace {

// The boundary halfedge leaving v, or an invalid handle when v is not on the boundary.
TriMesh::HalfedgeHandle outgoingBoundary(const TriMesh& mesh, TriMesh::VertexHandle v) {
  for (const auto h : mesh.voh_range(v))
    if (mesh.is_boundary(h)) return h;
  return TriMesh::HalfedgeHandle();
}

}  // namespace

std::string borderLoopProblem(const TriMesh& mesh, const std::vector<int>& vertex) {
  if (vertex.size() < 3) return "a border loop needs at least 3 vertices";
  const int n = int(mesh.n_vertices());
  for (std::size_t i = 0; i < vertex.size(); ++i) {
    const int v = vertex[i];
    if (v < 0 || v >= n) return "vertex " + std::to_string(v) + " is not a vertex of the mesh";
    const auto h = outgoingBoundary(mesh, TriMesh::VertexHandle(v));
    if (!h.is_valid()) return "vertex " + std::to_string(v) + " is not on the mesh's boundary";
    const int next = vertex[(i + 1) % vertex.size()];
    if (mesh.to_vertex_handle(h).idx() != next)
      return "vertices " + std::to_string(v) + " and " + std::to_string(next) +
             " are not joined by a boundary edge in the loop's direction";
  }
  return {};
}

std::vector<std::vector<int>> boundaryLoops(const TriMesh& mesh) {
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (const auto v : mesh.vertices()) {
    for (const auto start : mesh.voh_range(v)) {
      if (!mesh.is_boundary(start) || seen[std::size_t(start.idx())]) continue;
      std::vector<int> loop;
      auto h = start;
      do {
        seen[std::size_t(h.idx())] = 1;
        loop.push_back(mesh.from_vertex_handle(h).idx());
        h = mesh.next_halfedge_handle(h);
      } while (h != start && !seen[std::size_t(h.idx())]);
      std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
      loops.push_back(std::move(loop));
    }
  }
  std::sort(loops.begin(), loops.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return loops;
}

}  // namespace geobrush
