#include "geobrush/submesh.hpp"

#include <algorithm>

namespace geobrush {

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
  sub.surface.reserve(sub.sourceVertex.size(), sub.sourceVertex.size() + faces.size(),
                      faces.size());
  for (std::size_t i = 0; i < sub.sourceVertex.size(); ++i) {
    const int v = sub.sourceVertex[i];
    local[std::size_t(v)] = int(i);
    sub.surface.add_vertex(mesh.point(TriMesh::VertexHandle(v)));
  }
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
