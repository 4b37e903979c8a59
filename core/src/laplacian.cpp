#include "geobrush/laplacian.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/parallel.hpp"

namespace geobrush {
namespace {

// cot of the angle at `apex` between the edges to a and b; 0 for a degenerate corner.
double cotangent(const Eigen::Vector3d& apex, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d u = a - apex, w = b - apex;
  const double sine = u.cross(w).norm();
  if (!(sine > std::numeric_limits<double>::min() * 1e4 * u.norm() * w.norm())) return 0.0;
  return u.dot(w) / sine;
}

// The share of triangle (a, b, c) that belongs to corner a in the mixed Voronoi areas of Meyer et
// al. 2003: its Voronoi region where the triangle is not obtuse, else half the triangle where
// the obtuse angle is a's and a quarter where it is another's. The shares of the three corners
// sum to the triangle's area.
// cotC and cotB: cotangent(c, a, b) and cotangent(b, a, c), where the caller has them.
double mixedArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 double cotC, double cotB) {
  const double area = 0.5 * (b - a).cross(c - a).norm();
  if ((b - a).dot(c - a) < 0.0) return area / 2;
  if ((a - b).dot(c - b) < 0.0 || (a - c).dot(b - c) < 0.0) return area / 4;
  return ((b - a).squaredNorm() * cotC + (c - a).squaredNorm() * cotB) / 8.0;
}
double mixedArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return mixedArea(a, b, c, cotangent(c, a, b), cotangent(b, a, c));
}

struct Corners {
  std::array<int, 3> id;
  std::array<Eigen::Vector3d, 3> point;
};

Corners cornersOf(const TriMesh& mesh, TriMesh::FaceHandle face) {
  Corners corners;
  int k = 0;
  for (auto v : mesh.fv_range(face)) {
    corners.id[k] = v.idx();
    corners.point[k++] = pointOf(mesh, v);
  }
  return corners;
}

}  // namespace

Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh) {
  std::vector<int> faces(mesh.n_faces());
  for (std::size_t f = 0; f < faces.size(); ++f)
    faces[f] = int(f);
  return cotangentLaplacian(mesh, faces);
}

Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh, const std::vector<int>& faces) {
  std::vector<int> identity(mesh.n_vertices());
  for (std::size_t v = 0; v < identity.size(); ++v)
    identity[v] = int(v);
  return cotangentLaplacian(mesh, faces, identity, int(mesh.n_vertices()));
}

Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh, const std::vector<int>& faces,
                                               const std::vector<int>& index, int n) {
  // Each face writes its own twelve entries, in face order on any number of threads.
  std::vector<Eigen::Triplet<double>> entries(faces.size() * 12);
  parallelBlocks(faces.size(), 4096, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t f = first; f < last; ++f) {
      const auto [id, p] = cornersOf(mesh, TriMesh::FaceHandle(faces[f]));
      auto* entry = &entries[12 * f];
      for (int c = 0; c < 3; ++c) {
        const int i = index[std::size_t(id[(c + 1) % 3])];
        const int j = index[std::size_t(id[(c + 2) % 3])];
        const double w = cotangent(p[c], p[(c + 1) % 3], p[(c + 2) % 3]);
        *entry++ = {i, j, -w};
        *entry++ = {j, i, -w};
        *entry++ = {i, i, w};
        *entry++ = {j, j, w};
      }
    }
  });
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return laplacian;
}

Eigen::VectorXd vertexAreas(const TriMesh& mesh) {
  Eigen::VectorXd areas(Eigen::Index(mesh.n_vertices()));
  for (auto v : mesh.vertices())
    areas[v.idx()] = vertexArea(mesh, v.idx());
  return areas;
}

std::vector<Eigen::Vector3d> areaWeightedNormals(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> normals(mesh.n_vertices());
  for (auto v : mesh.vertices())
    normals[std::size_t(v.idx())] = areaWeightedNormal(mesh, v.idx());
  return normals;
}

Eigen::Vector3d cotangentLaplace(const TriMesh& mesh, int vertex) {
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();
  for (auto face : mesh.vf_range(TriMesh::VertexHandle(vertex))) {
    const auto [id, p] = cornersOf(mesh, face);
    const int c = id[0] == vertex ? 0 : id[1] == vertex ? 1 : 2;
    const int j = (c + 1) % 3, k = (c + 2) % 3;
    delta +=
        cotangent(p[k], p[c], p[j]) * (p[j] - p[c]) + cotangent(p[j], p[c], p[k]) * (p[k] - p[c]);
  }
  return delta;
}

double vertexArea(const TriMesh& mesh, int vertex) {
  double area = 0.0;
  for (auto face : mesh.vf_range(TriMesh::VertexHandle(vertex))) {
    const auto [id, p] = cornersOf(mesh, face);
    const int c = id[0] == vertex ? 0 : id[1] == vertex ? 1 : 2;
    area += mixedArea(p[c], p[(c + 1) % 3], p[(c + 2) % 3]);
  }
  return area;
}

Eigen::Vector3d areaWeightedNormal(const TriMesh& mesh, int vertex) {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (auto face : mesh.vf_range(TriMesh::VertexHandle(vertex))) {
    const auto [id, p] = cornersOf(mesh, face);
    normal += (p[1] - p[0]).cross(p[2] - p[0]);
  }
  const double length = normal.norm();
  return length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
}

// The same sums as the three functions above, in the same order, sharing each face's corners
// and the two cotangents that both the Laplacian and the mixed area use.
VertexGeometry vertexGeometry(const TriMesh& mesh, int vertex) {
  VertexGeometry geometry;
  geometry.laplace = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (auto face : mesh.vf_range(TriMesh::VertexHandle(vertex))) {
    const auto [id, p] = cornersOf(mesh, face);
    const int c = id[0] == vertex ? 0 : id[1] == vertex ? 1 : 2;
    const int j = (c + 1) % 3, k = (c + 2) % 3;
    const double cotK = cotangent(p[k], p[c], p[j]), cotJ = cotangent(p[j], p[c], p[k]);
    geometry.laplace += cotK * (p[j] - p[c]) + cotJ * (p[k] - p[c]);
    normal += (p[1] - p[0]).cross(p[2] - p[0]);
    geometry.area += mixedArea(p[c], p[j], p[k], cotK, cotJ);
  }
  const double length = normal.norm();
  geometry.normal = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
  return geometry;
}

MeshDifferentials meshDifferentials(const TriMesh& mesh) {
  MeshDifferentials differentials;
  differentials.laplacian = cotangentLaplacian(mesh);
  const std::size_t n = mesh.n_vertices();
  differentials.normals.resize(n);
  differentials.areas.resize(Eigen::Index(n));
  parallelBlocks(n, 4096, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t v = first; v < last; ++v) {
      const VertexGeometry geometry = vertexGeometry(mesh, int(v));
      differentials.normals[v] = geometry.normal;
      differentials.areas[Eigen::Index(v)] = geometry.area;
    }
  });
  return differentials;
}

std::shared_ptr<const MeshDifferentials> derivedMeshDifferentials(Context& ctx,
                                                                  const MeshPtr& mesh) {
  return ctx.derivedFrom("mesh_differentials", {mesh}, 0, [&] {
    return std::make_shared<const MeshDifferentials>(meshDifferentials(mesh->surface));
  });
}

std::string LaplacianSystem::summary() const {
  return "Laplacian system: " + std::to_string(vertices.size()) + " unknowns, " +
         std::to_string(boundary.size()) + " on the border";
}

Eigen::MatrixX3d pointMatrix(const TriMesh& mesh) {
  Eigen::MatrixX3d points(Eigen::Index(mesh.n_vertices()), 3);
  for (auto v : mesh.vertices())
    points.row(v.idx()) = pointOf(mesh, v).transpose();
  return points;
}

}  // namespace geobrush
