#include "geobrush/mesh_points.hpp"

#include <algorithm>
#include <cstring>

namespace geobrush {
namespace {

const auto& item(const TriMesh& mesh, TriMesh::VertexHandle v) {
  return mesh.vertex(v);
}
const auto& item(const TriMesh& mesh, TriMesh::EdgeHandle e) {
  return mesh.edge(e);
}
const auto& item(const TriMesh& mesh, TriMesh::FaceHandle f) {
  return mesh.face(f);
}

// The first `count` items of one kind, and their status flags, hold the same bytes in `a` and
// `b`: the kernel keeps each kind, and each status property, in one contiguous array of plain
// handles or flags.
template <typename Handle>
bool sameItems(const TriMesh& a, const TriMesh& b, std::size_t count) {
  if (count == 0) return true;
  const Handle first(0);
  return std::memcmp(&item(a, first), &item(b, first), count * sizeof(item(a, first))) == 0 &&
         std::memcmp(&a.status(first), &b.status(first), count * sizeof(a.status(first))) == 0;
}

}  // namespace

bool sameConnectivity(const TriMesh& a, const TriMesh& b) {
  return a.n_vertices() == b.n_vertices() && a.n_edges() == b.n_edges() &&
         a.n_faces() == b.n_faces() && sameItems<TriMesh::VertexHandle>(a, b, a.n_vertices()) &&
         sameItems<TriMesh::EdgeHandle>(a, b, a.n_edges()) &&
         sameItems<TriMesh::FaceHandle>(a, b, a.n_faces());
}

void copyPoints(const TriMesh& from, TriMesh& into) {
  const auto& points = from.property(from.points_pph()).data_vector();
  std::copy(points.begin(), points.end(), into.property(into.points_pph()).data_vector().begin());
}

}  // namespace geobrush
