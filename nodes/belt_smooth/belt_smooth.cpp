#include "belt_smooth.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace geobrush {
namespace {

void checkInputs(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                 const BeltSmoothOptions& options) {
  if (inRegion.size() != mesh.n_vertices())
    throw std::invalid_argument("the region has " + std::to_string(inRegion.size()) +
                                " entries for " + std::to_string(mesh.n_vertices()) + " vertices");
  if (options.rings < 1 || options.rings > 16) throw std::out_of_range("rings must be in 1..16");
  if (options.iterations < 0 || options.iterations > 1000)
    throw std::out_of_range("iterations must be in 0..1000");
  if (!(options.lambda > 0.0 && options.lambda <= 1.0))
    throw std::out_of_range("lambda must be in (0, 1]");
}

// The region's vertices with a neighbour outside it, ascending: every edge across the border
// starts at one.
std::vector<int> borderVertices(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion) {
  std::vector<int> border;
  for (std::size_t v = 0; v < inRegion.size(); ++v) {
    if (!inRegion[v]) continue;
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(int(v))))
      if (!inRegion[std::size_t(w.idx())]) {
        border.push_back(int(v));
        break;
      }
  }
  return border;
}

// The vertices fewer than `rings` rings from an edge across the border, by breadth-first search
// from the border, so that the cost follows the region rather than the mesh.
std::vector<int> beltAround(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                            const std::vector<int>& border, int rings) {
  std::vector<std::uint8_t> reached(mesh.n_vertices(), 0);
  std::vector<int> frontier;
  const auto reach = [&](int v, std::vector<int>& into) {
    if (reached[std::size_t(v)]) return;
    reached[std::size_t(v)] = 1;
    into.push_back(v);
  };
  for (int v : border)
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
      if (!inRegion[std::size_t(w.idx())]) {
        reach(v, frontier);
        reach(w.idx(), frontier);
      }
  std::vector<int> belt = frontier;
  for (int ring = 1; ring < rings; ++ring) {
    std::vector<int> next;
    for (int v : frontier)
      for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
        reach(w.idx(), next);
    belt.insert(belt.end(), next.begin(), next.end());
    frontier = std::move(next);
  }
  std::sort(belt.begin(), belt.end());
  return belt;
}

// The faces with corners on both sides of the border, ascending: each has a corner on the border.
std::vector<int> seamFacesAround(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                                 const std::vector<int>& border) {
  std::vector<int> faces;
  for (int v : border)
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v))) {
      int inside = 0;
      for (auto c : mesh.fv_range(f))
        inside += inRegion[std::size_t(c.idx())] ? 1 : 0;
      if (inside < 3) faces.push_back(f.idx());
    }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

}  // namespace

BeltSmoothResult smoothBelt(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                            const BeltSmoothOptions& options) {
  checkInputs(mesh, inRegion, options);
  TriMesh smoothed = mesh;
  BeltSmoothResult result = smoothBeltInPlace(smoothed, inRegion, options);
  result.mesh = std::move(smoothed);
  return result;
}

BeltSmoothResult smoothBeltInPlace(TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                                   const BeltSmoothOptions& options) {
  checkInputs(mesh, inRegion, options);
  BeltSmoothResult result;
  const std::vector<int> border = borderVertices(mesh, inRegion);
  result.belt = beltAround(mesh, inRegion, border, options.rings);
  std::vector<int> moving;
  for (int v : result.belt)
    if (!mesh.is_boundary(TriMesh::VertexHandle(v))) moving.push_back(v);
  std::vector<Eigen::Vector3d> next(moving.size());
  for (int pass = 0; pass < options.iterations; ++pass) {
    for (std::size_t i = 0; i < moving.size(); ++i) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      int count = 0;
      for (auto w : mesh.vv_range(TriMesh::VertexHandle(moving[i]))) {
        mean += pointOf(mesh, w.idx());
        ++count;
      }
      const Eigen::Vector3d p = pointOf(mesh, moving[i]);
      next[i] = count > 0 ? Eigen::Vector3d(p + options.lambda * (mean / count - p)) : p;
    }
    for (std::size_t i = 0; i < moving.size(); ++i)
      mesh.set_point(TriMesh::VertexHandle(moving[i]), {next[i].x(), next[i].y(), next[i].z()});
  }
  result.seamFaces = seamFacesAround(mesh, inRegion, border);
  return result;
}

}  // namespace geobrush
