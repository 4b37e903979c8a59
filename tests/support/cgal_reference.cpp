#include "cgal_reference.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

namespace geobrush::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh toCgal(const TriMesh& mesh) {
  SurfaceMesh out;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  vertices.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    vertices.push_back(out.add_vertex(Point(p[0], p[1], p[2])));
  }
  for (auto f : mesh.faces()) {
    std::vector<SurfaceMesh::Vertex_index> corners;
    for (auto v : mesh.fv_range(f))
      corners.push_back(vertices[std::size_t(v.idx())]);
    if (out.add_face(corners) == SurfaceMesh::null_face())
      throw std::runtime_error("CGAL refused a face of the mesh: it is not manifold");
  }
  return out;
}

TriMesh fromCgal(const SurfaceMesh& mesh) {
  TriMesh out;
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.add_vertex(TriMesh::Point(p.x(), p.y(), p.z()));
  }
  for (auto f : mesh.faces()) {
    std::vector<TriMesh::VertexHandle> corners;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      corners.push_back(TriMesh::VertexHandle(int(v)));
    out.add_face(corners);
  }
  return out;
}

}  // namespace

std::size_t cgalSelfIntersections(const TriMesh& mesh) {
  const SurfaceMesh surface = toCgal(mesh);
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections(surface, std::back_inserter(pairs));
  return pairs.size();
}

SurfaceDistance cgalDistances(const std::vector<Eigen::Vector3d>& points, const TriMesh& surface) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  const SurfaceMesh mesh = toCgal(surface);
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  SurfaceDistance distance;
  for (const auto& p : points) {
    const double d = std::sqrt(tree.squared_distance(Point(p.x(), p.y(), p.z())));
    distance.mean += d;
    distance.max = std::max(distance.max, d);
  }
  if (!points.empty()) distance.mean /= double(points.size());
  return distance;
}

CgalFill cgalFillHoles(const TriMesh& mesh, unsigned continuity, std::size_t maxBorderEdges) {
  SurfaceMesh surface = toCgal(mesh);
  std::vector<SurfaceMesh::Halfedge_index> borders;
  PMP::extract_boundary_cycles(surface, std::back_inserter(borders));
  CgalFill fill;
  for (auto h : borders) {
    std::size_t edges = 0;
    for (auto e : CGAL::halfedges_around_face(h, surface)) {
      (void)e;
      ++edges;
    }
    if (maxBorderEdges > 0 && edges > maxBorderEdges) continue;
    std::vector<SurfaceMesh::Face_index> newFaces;
    std::vector<SurfaceMesh::Vertex_index> newVertices;
    const auto done = PMP::triangulate_refine_and_fair_hole(
        surface, h, std::back_inserter(newFaces), std::back_inserter(newVertices),
        CGAL::parameters::fairing_continuity(continuity).density_control_factor(std::sqrt(2.0)));
    fill.newVertices += newVertices.size();
    if (std::get<0>(done)) ++fill.filledHoles;
  }
  fill.mesh = fromCgal(surface);
  return fill;
}

}  // namespace geobrush::test
