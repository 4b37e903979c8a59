#include "geobrush/mesh_points.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>

#include "geobrush/parallel.hpp"

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

// Megabyte blocks, compared or copied on every core: large meshes are memory-bound.
constexpr std::size_t kBlockBytes = std::size_t(1) << 20;

bool sameBytes(const void* a, const void* b, std::size_t bytes) {
  std::atomic<bool> same{true};
  const auto* left = static_cast<const unsigned char*>(a);
  const auto* right = static_cast<const unsigned char*>(b);
  parallelBlocks(bytes, kBlockBytes, 0, [&](std::size_t first, std::size_t last) {
    if (same.load(std::memory_order_relaxed) &&
        std::memcmp(left + first, right + first, last - first) != 0)
      same.store(false, std::memory_order_relaxed);
  });
  return same.load();
}

// The first `count` items of one kind, and their status flags, hold the same bytes in `a` and
// `b`: the kernel keeps each kind, and each status property, in one contiguous array of plain
// handles or flags.
template <typename Handle>
bool sameItems(const TriMesh& a, const TriMesh& b, std::size_t count) {
  if (count == 0) return true;
  const Handle first(0);
  return sameBytes(&item(a, first), &item(b, first), count * sizeof(item(a, first))) &&
         sameBytes(&a.status(first), &b.status(first), count * sizeof(a.status(first)));
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
  auto& target = into.property(into.points_pph()).data_vector();
  const std::size_t perBlock = kBlockBytes / sizeof(points.front());
  parallelBlocks(points.size(), perBlock, 0, [&](std::size_t first, std::size_t last) {
    std::copy(points.begin() + std::ptrdiff_t(first), points.begin() + std::ptrdiff_t(last),
              target.begin() + std::ptrdiff_t(first));
  });
}

void copyPoints(const TriMesh& from, const std::vector<int>& vertices, TriMesh& into) {
  for (int v : vertices)
    into.set_point(TriMesh::VertexHandle(v), from.point(TriMesh::VertexHandle(v)));
}

}  // namespace geobrush
