#include "emd_fixtures.hpp"

#include "direct_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

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

int farthestInDomain(const Parameterization& param, int from) {
  const Eigen::Vector2d& origin = param.uv[std::size_t(from)];
  std::size_t far = 0;
  for (std::size_t v = 0; v < param.uv.size(); ++v)
    if ((param.uv[v] - origin).norm() > (param.uv[far] - origin).norm()) far = v;
  return int(far);
}

RealMeshRegion bunnyRegion() {
  RealMeshRegion made;
  made.mesh = readMesh(meshPath("bunny_small.obj")).mesh;
  made.parameterization =
      projectedParameterization(made.mesh, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
  const Eigen::Vector2d centre = made.parameterization->uv[0];
  const double radius = 0.1 * boundingDiagonal(made.mesh->surface);
  const auto region =
      regionWhere(*made.parameterization, *made.parameterization,
                  [&](const Eigen::Vector2d& u) { return (u - centre).norm() < radius; });
  made.signal = runNode("geobrush.emd_signal", {{"mesh", made.mesh}}).get<VertexFields>("signal");
  made.system =
      runNode("geobrush.laplacian_system", {{"target", made.parameterization}, {"region", region}})
          .get<LaplacianSystem>("system");
  return made;
}

}  // namespace geobrush::test
