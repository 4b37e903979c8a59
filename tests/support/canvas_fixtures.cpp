#include "canvas_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <deque>

#include "geobrush/mesh_io.hpp"
#include "geobrush/submesh.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush::test {

MeshPtr heightGrid(int n, const std::function<double(double, double)>& z,
                   const Eigen::Isometry3d& rigid) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      const Eigen::Vector3d p = rigid * Eigen::Vector3d(x, y, z(x, y));
      mesh.add_vertex(toPoint(p));
    }
  auto at = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

std::shared_ptr<Parameterization> heightFieldParameterization(
    int n, const std::function<double(double, double)>& height) {
  auto canvas = std::make_shared<Canvas>();
  canvas->surface = heightGrid(n, height)->surface;
  const TriMesh& mesh = canvas->surface;
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

Canvas growDiscCanvas(const MeshPtr& mesh, int face, double radius) {
  const TriMesh& m = mesh->surface;
  const auto point = [&](TriMesh::VertexHandle v) {
    return Eigen::Vector3d(m.point(v)[0], m.point(v)[1], m.point(v)[2]);
  };
  Canvas canvas;
  canvas.source = mesh;
  const double weights[3] = {0.5, 0.3, 0.2};
  int k = 0;
  for (auto v : m.fv_range(TriMesh::FaceHandle(face)))
    canvas.originPoint += weights[k++] * point(v);
  auto painted = [&](TriMesh::FaceHandle f) {
    for (auto v : m.fv_range(f))
      if ((point(v) - canvas.originPoint).norm() > radius) return false;
    return true;
  };
  std::vector<char> reached(m.n_faces(), 0);
  std::vector<int> region;
  std::deque<int> queue{face};
  reached[face] = 1;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    region.push_back(f);
    for (auto g : m.ff_range(TriMesh::FaceHandle(f))) {
      if (reached[g.idx()] || !painted(g)) continue;
      reached[g.idx()] = 1;
      queue.push_back(g.idx());
    }
  }
  std::sort(region.begin(), region.end());
  Submesh sub = extractSubmesh(m, region);
  EXPECT_EQ(sub.unattachedFace, -1);
  canvas.surface = std::move(sub.surface);
  canvas.sourceVertex = std::move(sub.sourceVertex);
  canvas.sourceFace = std::move(sub.sourceFace);
  canvas.originFace = int(std::find(region.begin(), region.end(), face) - region.begin());
  EXPECT_EQ(topology(canvas.surface).boundaryLoops, 1u);
  for (auto h : canvas.surface.halfedges()) {
    if (!canvas.surface.is_boundary(h)) continue;
    auto g = h;
    do {
      canvas.boundary.push_back(canvas.surface.from_vertex_handle(g).idx());
      g = canvas.surface.next_halfedge_handle(g);
    } while (g != h);
    break;
  }
  const int originSource = m.cfv_begin(TriMesh::FaceHandle(face))->idx();
  canvas.originVertex =
      int(std::lower_bound(canvas.sourceVertex.begin(), canvas.sourceVertex.end(), originSource) -
          canvas.sourceVertex.begin());
  return canvas;
}

std::shared_ptr<Parameterization> flatDiscParameterization(const MeshPtr& mesh, int face,
                                                           double radius) {
  auto canvas = std::make_shared<Canvas>(growDiscCanvas(mesh, face, radius));
  auto param = std::make_shared<Parameterization>();
  for (auto v : canvas->surface.vertices()) {
    param->uv.emplace_back(canvas->surface.point(v)[0], canvas->surface.point(v)[1]);
    param->normal.push_back(Eigen::Vector3d::UnitZ());
  }
  param->canvas = canvas;
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

namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

bool segmentsCross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d) {
  const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
  const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
  return ((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) &&
         ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0) && !(d1 == 0 && d2 == 0 && d3 == 0);
}

}  // namespace

bool boundaryIsSimple(const Canvas& canvas, const std::vector<Eigen::Vector2d>& uv) {
  const auto& b = canvas.boundary;
  const std::size_t m = b.size();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;
      if (segmentsCross(uv[b[i]], uv[b[(i + 1) % m]], uv[b[j]], uv[b[(j + 1) % m]])) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace geobrush::test
