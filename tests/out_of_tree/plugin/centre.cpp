#include "centre.hpp"

#include <stdexcept>

namespace example {

CentreResult centreMesh(const geobrush::TriMesh& mesh) {
  OpenMesh::Vec3d weighted(0, 0, 0);
  double area = 0;
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    const auto& a = mesh.point(mesh.from_vertex_handle(h));
    const auto& b = mesh.point(mesh.to_vertex_handle(h));
    const auto& c = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
    const double faceArea = 0.5 * ((b - a) % (c - a)).norm();
    weighted += faceArea * (a + b + c) / 3.0;
    area += faceArea;
  }
  if (!(area > 0)) throw std::invalid_argument("the mesh has no area");
  CentreResult result{mesh, -weighted / area};
  for (auto v : result.mesh.vertices())
    result.mesh.point(v) += result.shift;
  return result;
}

}  // namespace example
