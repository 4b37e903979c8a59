#include "emd_fixtures.hpp"

#include "geobrush/laplacian.hpp"

namespace geobrush::test {

std::shared_ptr<const Parameterization> projectedParameterization(const MeshPtr& mesh,
                                                                  const Eigen::Vector3d& u,
                                                                  const Eigen::Vector3d& v) {
  auto canvas = std::make_shared<Canvas>();
  canvas->source = mesh;
  canvas->surface = mesh->surface;
  auto param = std::make_shared<Parameterization>();
  for (auto vertex : mesh->surface.vertices()) {
    const auto& p = mesh->surface.point(vertex);
    const Eigen::Vector3d point(p[0], p[1], p[2]);
    canvas->sourceVertex.push_back(vertex.idx());
    param->uv.emplace_back(point.dot(u), point.dot(v));
    param->normal.push_back(u.cross(v).normalized());
  }
  for (auto face : mesh->surface.faces())
    canvas->sourceFace.push_back(face.idx());
  param->canvas = canvas;
  return param;
}

std::shared_ptr<const Region2D> regionWhere(
    const Parameterization& source, const Parameterization& target,
    const std::function<bool(const Eigen::Vector2d&)>& inside) {
  auto region = std::make_shared<Region2D>();
  for (std::size_t i = 0; i < source.uv.size(); ++i)
    if (inside(source.uv[i])) region->sourceVertices.push_back(int(i));
  for (std::size_t i = 0; i < target.uv.size(); ++i)
    if (inside(target.uv[i])) region->targetVertices.push_back(int(i));
  return region;
}

std::vector<double> wholeMeshSignal(const TriMesh& mesh) {
  const Eigen::MatrixX3d delta = -(cotangentLaplacian(mesh) * pointMatrix(mesh));
  const auto normals = areaWeightedNormals(mesh);
  std::vector<double> g(mesh.n_vertices());
  for (std::size_t i = 0; i < g.size(); ++i)
    g[i] = delta.row(Eigen::Index(i)).dot(normals[i]);
  return g;
}

}  // namespace geobrush::test
