#include "geobrush/mesh.hpp"

#include <Eigen/Geometry>

#include <string>

#include "mesh_hash.hpp"

namespace geobrush {

void hashGeometry(Hasher& hasher, const TriMesh& mesh) {
  hasher.u64(mesh.n_vertices());
  for (auto vertex : mesh.vertices()) {
    const auto& point = mesh.point(vertex);
    hasher.f64(point[0]).f64(point[1]).f64(point[2]);
  }
  hasher.u64(mesh.n_faces());
  for (auto face : mesh.faces())
    for (auto vertex : mesh.fv_range(face))
      hasher.u64(std::uint64_t(vertex.idx()));
}

Hash Mesh::contentHash() const {
  Hasher hasher;
  hashGeometry(hasher.str(kTypeId), surface);
  hasher.u64(vertexColors.size());
  for (const Rgb& color : vertexColors)
    hasher.f64(color[0]).f64(color[1]).f64(color[2]);
  return hasher.digest();
}

std::string Mesh::summary() const {
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  return count(surface.n_vertices(), "vertex", "vertices") + ", " +
         count(surface.n_faces(), "face", "faces");
}

std::vector<Eigen::Vector3d> vertexPoints(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices())
    points.push_back(pointOf(mesh, v));
  return points;
}

double boundingDiagonal(const TriMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  return box.isEmpty() ? 0.0 : box.diagonal().norm();
}

double meanEdgeLength(const TriMesh& mesh) {
  if (mesh.n_edges() == 0) return 0;
  double sum = 0;
  for (auto e : mesh.edges())
    sum += mesh.calc_edge_length(e);
  return sum / double(mesh.n_edges());
}

}  // namespace geobrush
