#include "base_fixtures.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "geobrush/cut_paste.hpp"

namespace geobrush::test {
namespace {

using Eigen::Vector3d;

}  // namespace

CanvasPtr canvasOf(const MeshPtr& mesh, std::vector<int> faces) {
  const int first = *std::min_element(faces.begin(), faces.end());
  Vector3d centre = Vector3d::Zero();
  for (auto v : mesh->surface.fv_range(TriMesh::FaceHandle(first)))
    centre += pointOf(mesh->surface, v.idx()) / 3;
  return std::make_shared<const Canvas>(canvasFromFaces(mesh, std::move(faces), first, centre));
}

MeshPtr centroidFan(const Canvas& feature, const std::vector<int>& split) {
  const int n = int(feature.boundary.size());
  TriMesh base;
  Vector3d centroid = Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Vector3d p = pointOf(feature.surface, feature.boundary[i]);
    base.add_vertex(toPoint(p));
    centroid += p / n;
  }
  std::vector<int> loop;
  for (int i = 0; i < n; ++i) {
    loop.push_back(i);
    if (std::find(split.begin(), split.end(), i) == split.end()) continue;
    const Vector3d p = 0.5 * (pointOf(base, i) + pointOf(base, (i + 1) % n));
    loop.push_back(int(base.n_vertices()));
    base.add_vertex(toPoint(p));
  }
  const auto c = base.add_vertex(toPoint(centroid));
  for (std::size_t k = 0; k < loop.size(); ++k)  // faces hold the boundary edges as next -> current
    base.add_face(c, TriMesh::VertexHandle(loop[(k + 1) % loop.size()]),
                  TriMesh::VertexHandle(loop[k]));
  return std::make_shared<const Mesh>(base);
}

MeshPtr membraneBase(const Canvas& feature, int iterations, const std::vector<int>& split) {
  const TriMesh& f = feature.surface;
  const int n = int(feature.boundary.size());
  std::vector<int> index(f.n_vertices(), -1);
  int next = 0;
  for (int v : feature.boundary)
    index[v] = next++;
  for (auto v : f.vertices())
    if (index[v.idx()] < 0) index[v.idx()] = next++;
  std::vector<int> original(f.n_vertices());
  for (auto v : f.vertices())
    original[index[v.idx()]] = v.idx();
  TriMesh smooth;
  for (int v : original)
    smooth.add_vertex(f.point(TriMesh::VertexHandle(v)));
  std::vector<std::array<int, 3>> faces;
  for (auto face : f.faces()) {
    std::array<int, 3> c;
    int k = 0;
    for (auto v : f.fv_range(face))
      c[k++] = index[v.idx()];
    faces.push_back(c);
    smooth.add_face(TriMesh::VertexHandle(c[0]), TriMesh::VertexHandle(c[1]),
                    TriMesh::VertexHandle(c[2]));
  }
  std::vector<char> movable(smooth.n_vertices(), 0);
  std::fill(movable.begin() + n, movable.end(), 1);
  umbrellaSmooth(smooth, movable, iterations);
  TriMesh base;
  for (auto v : smooth.vertices())
    base.add_vertex(smooth.point(v));
  for (int i : split) {  // the face holding i + 1 -> i gets the midpoint m: (p, i+1, m), (p, m, i)
    const int m = base.add_vertex(0.5 * (base.point(TriMesh::VertexHandle(i)) +
                                         base.point(TriMesh::VertexHandle((i + 1) % n))))
                      .idx();
    for (std::size_t k = 0, count = faces.size(); k < count; ++k)
      for (int r = 0; r < 3; ++r) {
        const std::array<int, 3> c = faces[k];
        if (c[(r + 1) % 3] != (i + 1) % n || c[(r + 2) % 3] != i) continue;
        faces[k][(r + 2) % 3] = m;
        faces.push_back({c[r], m, i});
        break;
      }
  }
  for (const auto& c : faces)
    base.add_face(TriMesh::VertexHandle(c[0]), TriMesh::VertexHandle(c[1]),
                  TriMesh::VertexHandle(c[2]));
  return std::make_shared<const Mesh>(base);
}

int nearestFace(const TriMesh& mesh, const Vector3d& p) {
  int best = 0;
  double bestDistance = INFINITY;
  for (auto f : mesh.faces()) {
    Vector3d c = Vector3d::Zero();
    for (auto v : mesh.fv_range(f))
      c += pointOf(mesh, v.idx()) / 3;
    if ((c - p).norm() < bestDistance)
      std::tie(bestDistance, best) = std::tuple((c - p).norm(), f.idx());
  }
  return best;
}

}  // namespace geobrush::test
