#include "laplacian_system.hpp"

#include <algorithm>
#include <future>
#include <stdexcept>
#include <string>

#include "geobrush/parallel.hpp"
#include "geobrush/vertex_fields.hpp"

namespace geobrush {
namespace {

using Sparse = LaplacianSystem::Sparse;

void checkInputs(const TriMesh& mesh, const std::vector<int>& vertices,
                 const LaplacianSystemOptions& options) {
  if (!(options.mu > 0.0 && options.mu <= 1e6) ||
      !(options.muBoundary > 0.0 && options.muBoundary <= 1e6))
    throw std::out_of_range("mu and mu_boundary must be in (0, 1e6]");
  if (vertices.empty()) throw std::invalid_argument("the region is empty");
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i] < 0 || std::size_t(vertices[i]) >= mesh.n_vertices())
      throw std::invalid_argument("the region names vertex " + std::to_string(vertices[i]) +
                                  ", which the mesh lacks");
    if (i > 0 && vertices[i] <= vertices[i - 1])
      throw std::invalid_argument("the region's vertices are not ascending and distinct");
  }
}

// The faces the operator reads, ascending: around the region (anchor) or within it (drop).
std::vector<int> operatorFaces(const TriMesh& mesh, const std::vector<int>& unknown,
                               const std::vector<int>& vertices, OutsideNeighbours outside) {
  std::vector<std::uint8_t> read(mesh.n_faces(), 0);
  for (int v : vertices)
    for (auto f : mesh.vf_range(TriMesh::VertexHandle(v))) {
      bool within = true;
      for (auto c : mesh.fv_range(f))
        within = within && unknown[std::size_t(c.idx())] >= 0;
      if (within || outside == OutsideNeighbours::anchor) read[std::size_t(f.idx())] = 1;
    }
  std::vector<int> faces;
  for (std::size_t f = 0; f < read.size(); ++f)
    if (read[f]) faces.push_back(int(f));
  return faces;
}

// The vertices the faces touch, ascending, and each one's position among them (-1 elsewhere).
struct Touched {
  std::vector<int> vertices;
  std::vector<int> position;
};

Touched touchedBy(const TriMesh& mesh, const std::vector<int>& faces) {
  Touched touched;
  touched.position.assign(mesh.n_vertices(), -1);
  for (int f : faces)
    for (auto c : mesh.fv_range(TriMesh::FaceHandle(f)))
      touched.position[std::size_t(c.idx())] = 0;
  for (std::size_t v = 0; v < touched.position.size(); ++v)
    if (touched.position[v] == 0) {
      touched.position[v] = int(touched.vertices.size());
      touched.vertices.push_back(int(v));
    }
  return touched;
}

// L restricted to the unknowns, and what the fixed vertices add to their rows of L V. The
// operator is built on the vertices its faces touch alone, columns in mesh order.
void restrictOperator(const TriMesh& mesh, const std::vector<int>& faces,
                      const std::vector<int>& unknown, LaplacianSystem& system) {
  const Touched touched = touchedBy(mesh, faces);
  const Sparse local =
      cotangentLaplacian(mesh, faces, touched.position, int(touched.vertices.size()));
  const int n = int(system.vertices.size());
  std::vector<Eigen::Triplet<double>> entries;
  system.fixedShare = Eigen::MatrixX3d::Zero(n, 3);
  for (int col = 0; col < local.outerSize(); ++col) {
    const int vertex = touched.vertices[std::size_t(col)];
    for (Sparse::InnerIterator it(local, col); it; ++it) {
      const int row = unknown[std::size_t(touched.vertices[std::size_t(it.row())])];
      if (row < 0) continue;
      if (const int c = unknown[std::size_t(vertex)]; c >= 0) {
        entries.emplace_back(row, c, it.value());
      } else {
        const auto& p = mesh.point(TriMesh::VertexHandle(vertex));
        system.fixedShare.row(row) += it.value() * Eigen::RowVector3d(p[0], p[1], p[2]);
      }
    }
  }
  system.laplacian.resize(n, n);
  system.laplacian.setFromTriplets(entries.begin(), entries.end());
}

// The same from the whole mesh's operator, where the region reads every face around it (anchor):
// an unknown's row of L then sums the same faces' terms in the same order, so the entries are bit
// for bit those of the operator on the faces alone. Column c is the unknown's own column of the
// whole operator (symmetric, term for term), rows ascending as the unknowns are.
void restrictWholeOperator(const TriMesh& mesh, const Sparse& whole,
                           const std::vector<int>& unknown, LaplacianSystem& system) {
  const int n = int(system.vertices.size());
  system.fixedShare = Eigen::MatrixX3d::Zero(n, 3);
  system.laplacian.resize(n, n);
  system.laplacian.reserve(Eigen::Index(8) * n);
  for (int c = 0; c < n; ++c) {
    system.laplacian.startVec(c);
    for (Sparse::InnerIterator it(whole, system.vertices[std::size_t(c)]); it; ++it) {
      if (const int row = unknown[std::size_t(it.row())]; row >= 0) {
        system.laplacian.insertBack(row, c) = it.value();
      } else {
        const auto& p = mesh.point(TriMesh::VertexHandle(int(it.row())));
        system.fixedShare.row(c) += it.value() * Eigen::RowVector3d(p[0], p[1], p[2]);
      }
    }
  }
  system.laplacian.finalize();
}

// mu per unknown: mu_boundary on the region's border (a vertex of the mesh's boundary or with a
// neighbour outside the region), mu elsewhere.
void pullTowardsOriginal(const TriMesh& mesh, const std::vector<int>& unknown,
                         const LaplacianSystemOptions& options, LaplacianSystem& system) {
  const int n = int(system.vertices.size());
  system.mu = Eigen::VectorXd::Constant(n, options.mu);
  for (int i = 0; i < n; ++i) {
    const TriMesh::VertexHandle v(system.vertices[std::size_t(i)]);
    bool border = mesh.is_boundary(v);
    for (auto w : mesh.vv_range(v))
      border = border || unknown[std::size_t(w.idx())] < 0;
    if (border) {
      system.boundary.push_back(i);
      system.mu[i] = options.muBoundary;
    }
  }
}

// L + M (screened) or L^T L + M^2 (Eq. 8's normal equations).
Sparse systemMatrix(const LaplacianSystem& system, LaplacianForm form) {
  const Eigen::Index n = system.mu.size();
  Sparse pull(n, n);
  pull.reserve(Eigen::VectorXi::Constant(n, 1));
  for (Eigen::Index i = 0; i < n; ++i)
    pull.insert(i, i) =
        form == LaplacianForm::screened ? system.mu[i] : system.mu[i] * system.mu[i];
  return form == LaplacianForm::screened
             ? Sparse(system.laplacian + pull)
             : Sparse(Sparse(system.laplacian.transpose() * system.laplacian) + pull);
}

std::shared_ptr<const Eigen::SimplicialLDLT<Sparse>> factorOf(const Sparse& matrix) {
  auto factor = std::make_shared<Eigen::SimplicialLDLT<Sparse>>(matrix);
  if (factor->info() != Eigen::Success)
    throw std::runtime_error("the region's system could not be factored");
  return factor;
}

// Per unknown: the original normal, point and area, and the original's Laplacian coordinates
// less their normal part. Each row is its own vertex's, so the blocks run on any number of
// threads with the same result.
// With the whole mesh's differentials, the normals and areas are read from them.
void describeUnknowns(const TriMesh& mesh, const MeshDifferentials* whole,
                      LaplacianSystem& system) {
  const int n = int(system.vertices.size());
  system.normals.resize(n, 3);
  system.points.resize(n, 3);
  system.area.resize(n);
  parallelBlocks(std::size_t(n), 2048, whole ? 1 : 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const TriMesh::VertexHandle v(system.vertices[i]);
      system.points.row(Eigen::Index(i)) = pointOf(mesh, v).transpose();
      if (whole) {
        system.normals.row(Eigen::Index(i)) = whole->normals[std::size_t(v.idx())].transpose();
        system.area[Eigen::Index(i)] = whole->areas[v.idx()];
        continue;
      }
      const VertexGeometry geometry = vertexGeometry(mesh, v.idx());
      system.normals.row(Eigen::Index(i)) = geometry.normal.transpose();
      system.area[Eigen::Index(i)] = geometry.area;
    }
  });
  const Eigen::MatrixX3d delta = system.laplacian * system.points + system.fixedShare;
  const Eigen::VectorXd along = delta.cwiseProduct(system.normals).rowwise().sum();
  system.tangential = delta - along.asDiagonal() * system.normals;
}

// The mesh's geometryHash stands for its points and faces, so the faces read need no hashing.
Hash systemKey(Hash meshHash, const std::vector<int>& vertices,
               const LaplacianSystemOptions& options) {
  Hasher hasher;
  hasher.str(LaplacianSystem::kTypeId).u64(meshHash);
  hasher.span(std::span<const int>(vertices));
  return hasher.f64(options.mu)
      .f64(options.muBoundary)
      .u64(std::uint64_t(options.outside))
      .u64(std::uint64_t(options.form))
      .digest();
}

}  // namespace

LaplacianSystem buildLaplacianSystem(const MeshPtr& mesh, const std::vector<int>& vertices,
                                     const LaplacianSystemOptions& options, Hash meshHash,
                                     const MeshDifferentials* whole) {
  const TriMesh& surface = mesh->surface;
  checkInputs(surface, vertices, options);
  LaplacianSystem system;
  system.mesh = mesh;
  system.meshHash = meshHash != 0 ? meshHash : geometryHash(surface);
  system.vertices = vertices;
  const int n = int(vertices.size());
  std::vector<int> unknown(surface.n_vertices(), -1);
  for (int i = 0; i < n; ++i)
    unknown[std::size_t(vertices[std::size_t(i)])] = i;

  if (whole && whole->normals.size() != surface.n_vertices())
    throw std::invalid_argument("the differentials are of another mesh");
  if (whole && options.outside == OutsideNeighbours::anchor) {
    restrictWholeOperator(surface, whole->laplacian, unknown, system);
  } else {
    const std::vector<int> faces = operatorFaces(surface, unknown, vertices, options.outside);
    restrictOperator(surface, faces, unknown, system);
  }
  pullTowardsOriginal(surface, unknown, options, system);
  system.form = options.form;
  // The factorization, the longest stage, runs beside the rest.
  auto factoring =
      std::async(std::launch::async | std::launch::deferred,
                 [matrix = systemMatrix(system, options.form)] { return factorOf(matrix); });
  describeUnknowns(surface, whole, system);
  system.key = systemKey(system.meshHash, vertices, options);
  system.factor = factoring.get();
  return system;
}

}  // namespace geobrush
