#include "geobrush/submesh.hpp"

#include <algorithm>

namespace geobrush {

Submesh extractSubmesh(const TriMesh& mesh, const std::vector<int>& faces) {
  Submesh sub;
  for (int f : faces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      sub.sourceVertex.push_back(v.idx());
  std::sort(sub.sourceVertex.begin(), sub.sourceVertex.end());
  sub.sourceVertex.erase(std::unique(sub.sourceVertex.begin(), sub.sourceVertex.end()),
                         sub.sourceVertex.end());
  for (int v : sub.sourceVertex)
    sub.surface.add_vertex(mesh.point(TriMesh::VertexHandle(v)));
  const auto local = [&](int v) {
    return TriMesh::VertexHandle(
        int(std::lower_bound(sub.sourceVertex.begin(), sub.sourceVertex.end(), v) -
            sub.sourceVertex.begin()));
  };
  std::vector<TriMesh::VertexHandle> corners;
  for (int f : faces) {
    corners.clear();
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      corners.push_back(local(v.idx()));
    if (!sub.surface.add_face(corners).is_valid()) {
      sub.unattachedFace = f;
      break;
    }
    sub.sourceFace.push_back(f);
  }
  return sub;
}

}  // namespace geobrush
