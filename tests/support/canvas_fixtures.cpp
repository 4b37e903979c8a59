#include "canvas_fixtures.hpp"

#include "geobrush/mesh_io.hpp"
#include "test_support.hpp"

namespace geobrush::test {

std::shared_ptr<Parameterization> heightFieldParameterization(
    int n, const std::function<double(double, double)>& height) {
  auto canvas = std::make_shared<Canvas>();
  TriMesh& mesh = canvas->surface;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      mesh.add_vertex({x, y, height(x, y)});
    }
  auto vh = [&](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(vh(i, j), vh(i + 1, j), vh(i + 1, j + 1));
      mesh.add_face(vh(i, j), vh(i + 1, j + 1), vh(i, j + 1));
    }
  for (int v = 0; v < int(mesh.n_vertices()); ++v)
    canvas->sourceVertex.push_back(v);
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  for (auto v : mesh.vertices()) {
    param->uv.emplace_back(mesh.point(v)[0], mesh.point(v)[1]);
    param->normal.push_back(Eigen::Vector3d::UnitZ());
  }
  return param;
}

std::shared_ptr<Parameterization> terrainParameterization() {
  auto canvas = std::make_shared<Canvas>();
  canvas->surface = readMesh(meshPath("mountain.obj")).mesh->surface;
  auto param = std::make_shared<Parameterization>();
  param->canvas = canvas;
  for (auto v : canvas->surface.vertices()) {
    const auto& p = canvas->surface.point(v);
    param->uv.emplace_back(p[0], -p[2]);
    param->normal.push_back(Eigen::Vector3d::UnitY());
  }
  return param;
}

}  // namespace geobrush::test
