#include "mesh_checks.hpp"

#include <map>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>

namespace geobrush::test {
namespace {

std::array<TriMesh::Point, 3> corners(const TriMesh& mesh, TriMesh::FaceHandle face) {
  std::array<TriMesh::Point, 3> p;
  int i = 0;
  for (auto v : mesh.fv_range(face))
    p[i++] = mesh.point(v);
  return p;
}

// Smallest set representative with path halving.
int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

Mesh tetrahedron(const std::array<OpenMesh::Vec3d, 4>& corners) {
  TriMesh mesh;
  std::array<TriMesh::VertexHandle, 4> v;
  for (int i = 0; i < 4; ++i)
    v[i] = mesh.add_vertex(corners[i]);
  mesh.add_face(v[0], v[2], v[1]);
  mesh.add_face(v[0], v[1], v[3]);
  mesh.add_face(v[0], v[3], v[2]);
  mesh.add_face(v[1], v[2], v[3]);
  return Mesh(std::move(mesh));
}

TriMesh unitSquareGrid(int n) {
  TriMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.add_vertex(TriMesh::Point(double(i) / n, double(j) / n, 0));
  auto id = [n](int i, int j) { return TriMesh::VertexHandle(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh;
}

TriMesh icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& x : p)
    x.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[std::size_t(a)] + p[std::size_t(b)]).normalized());
      return mid[key] = int(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& [a, b, c] : f) {
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(next);
  }
  TriMesh mesh;
  for (const auto& x : p)
    mesh.add_vertex(toPoint(x));
  for (const auto& [a, b, c] : f)
    mesh.add_face(TriMesh::VertexHandle(a), TriMesh::VertexHandle(b), TriMesh::VertexHandle(c));
  return mesh;
}

TriMesh boxCage(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n) {
  TriMesh mesh;
  std::map<std::array<int, 3>, TriMesh::VertexHandle> lattice;
  auto vertex = [&](std::array<int, 3> ijk) {
    auto [it, added] = lattice.try_emplace(ijk);
    if (added) {
      Eigen::Vector3d p;
      for (int a = 0; a < 3; ++a)
        p[a] = lo[a] + (hi[a] - lo[a]) * ijk[std::size_t(a)] / n;
      it->second = mesh.add_vertex(toPoint(p));
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // e_u x e_v = e_axis
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> ijk{};
            ijk[std::size_t(axis)] = side;
            ijk[std::size_t(u)] = i + di;
            ijk[std::size_t(v)] = j + dj;
            return vertex(ijk);
          };
          const auto c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1), c01 = corner(0, 1);
          if (side == n) {
            mesh.add_face(c00, c10, c11);
            mesh.add_face(c00, c11, c01);
          } else {
            mesh.add_face(c00, c11, c10);
            mesh.add_face(c00, c01, c11);
          }
        }
      }
    }
  }
  return mesh;
}

double surfaceArea(const TriMesh& mesh) {
  double area = 0;
  for (auto face : mesh.faces()) {
    const auto p = corners(mesh, face);
    area += 0.5 * ((p[1] - p[0]) % (p[2] - p[0])).norm();
  }
  return area;
}

double signedVolume(const TriMesh& mesh) {
  double volume = 0;
  for (auto face : mesh.faces()) {
    const auto p = corners(mesh, face);
    volume += (p[0] | (p[1] % p[2])) / 6.0;
  }
  return volume;
}

Topology topology(const TriMesh& mesh) {
  Topology t;
  t.vertices = mesh.n_vertices();
  t.edges = mesh.n_edges();
  t.faces = mesh.n_faces();
  t.eulerCharacteristic =
      static_cast<long>(t.vertices) - static_cast<long>(t.edges) + static_cast<long>(t.faces);

  std::vector<bool> visited(mesh.n_halfedges(), false);
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h)) continue;
    ++t.boundaryHalfedges;
    if (visited[h.idx()]) continue;
    ++t.boundaryLoops;
    for (auto walk = h; !visited[walk.idx()]; walk = mesh.next_halfedge_handle(walk)) {
      visited[walk.idx()] = true;
    }
  }

  std::vector<int> parent(mesh.n_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  for (auto face : mesh.faces()) {
    const int first = findRoot(parent, mesh.to_vertex_handle(mesh.halfedge_handle(face)).idx());
    for (auto v : mesh.fv_range(face))
      parent[findRoot(parent, v.idx())] = first;
  }
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v)) {
      ++t.isolatedVertices;
    } else {
      if (findRoot(parent, v.idx()) == v.idx()) ++t.components;
      if (!mesh.is_manifold(v)) ++t.nonManifoldVertices;
    }
  }
  return t;
}

double minAngleDegrees(const TriMesh& mesh) {
  double smallest = 180;
  for (auto face : mesh.faces()) {
    const auto p = corners(mesh, face);
    for (int i = 0; i < 3; ++i) {
      const auto a = p[(i + 1) % 3] - p[i];
      const auto b = p[(i + 2) % 3] - p[i];
      const double angle = std::atan2((a % b).norm(), a | b);
      smallest = std::min(smallest, angle * 180 / std::numbers::pi);
    }
  }
  return smallest;
}

std::size_t closeVertexPairs(const TriMesh& mesh, double tolerance) {
  std::vector<TriMesh::Point> points(mesh.points(), mesh.points() + mesh.n_vertices());
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = i + 1; j < points.size() && points[j][0] - points[i][0] < tolerance; ++j) {
      if ((points[j] - points[i]).norm() < tolerance) ++pairs;
    }
  }
  return pairs;
}

std::vector<std::array<int, 3>> faceIndices(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(mesh.n_faces());
  for (auto face : mesh.faces()) {
    std::array<int, 3> f;
    int i = 0;
    for (auto v : mesh.fv_range(face))
      f[i++] = v.idx();
    faces.push_back(f);
  }
  return faces;
}

bool bitIdentical(const TriMesh& a, const TriMesh& b) {
  return a.n_vertices() == b.n_vertices() &&
         std::memcmp(a.points(), b.points(), a.n_vertices() * sizeof(TriMesh::Point)) == 0 &&
         faceIndices(a) == faceIndices(b);
}

TriMesh withAnEdgeFlipped(const TriMesh& mesh) {
  TriMesh flipped = mesh;
  for (auto e : flipped.edges())
    if (!flipped.is_boundary(e) && flipped.is_flip_ok(e)) {
      flipped.flip(e);
      break;
    }
  return flipped;
}

bool sameHalfedgeStructure(const TriMesh& a, const TriMesh& b) {
  if (a.n_vertices() != b.n_vertices() || a.n_edges() != b.n_edges() ||
      a.n_faces() != b.n_faces() ||
      std::memcmp(a.points(), b.points(), a.n_vertices() * sizeof(TriMesh::Point)) != 0)
    return false;
  for (auto v : a.vertices())
    if (a.halfedge_handle(v) != b.halfedge_handle(v)) return false;
  for (auto f : a.faces())
    if (a.halfedge_handle(f) != b.halfedge_handle(f)) return false;
  for (auto h : a.halfedges())
    if (a.to_vertex_handle(h) != b.to_vertex_handle(h) || a.face_handle(h) != b.face_handle(h) ||
        a.next_halfedge_handle(h) != b.next_halfedge_handle(h) ||
        a.prev_halfedge_handle(h) != b.prev_halfedge_handle(h))
      return false;
  return true;
}

std::vector<double> edgeLengths(const TriMesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.n_edges());
  for (auto e : mesh.edges())
    lengths.push_back(mesh.calc_edge_length(e));
  return lengths;
}

}  // namespace geobrush::test
