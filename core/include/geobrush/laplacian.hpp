// The cotangent Laplacian and the per-vertex quantities that go with it (vertex areas, area-
// weighted normals), shared by the EMD detail transfer's nodes.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// L with L_ij = -(cot a_ij + cot b_ij) for each edge ij and L_ii = -sum_j L_ij: the
// unnormalized cotangent Laplacian of EMD detail transfer Eq. 7, symmetric positive
// semi-definite, so that -(L V)_i = sum_j w_ij (v_j - v_i) is Eq. 1's Delta(v_i). A boundary edge
// has one cotangent. A corner of a face with no area contributes nothing.
Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh);
// The same n x n operator from the given faces only (the open mesh they form).
Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh, const std::vector<int>& faces);
// The same on the vertices the faces touch alone: `index` maps each of their corners to its row
// and column in [0, size), so that a small patch of a large mesh costs the patch's size.
Eigen::SparseMatrix<double> cotangentLaplacian(const TriMesh& mesh, const std::vector<int>& faces,
                                               const std::vector<int>& index, int size);

// The mixed Voronoi area of each vertex (Meyer et al. 2003; the lumped mass): the areas of the
// mesh's faces shared out among their corners, so that they sum to the surface's area.
Eigen::VectorXd vertexAreas(const TriMesh& mesh);

// The unit normal of each vertex: its faces' normals weighted by their areas (zero where every
// face around it is degenerate).
std::vector<Eigen::Vector3d> areaWeightedNormals(const TriMesh& mesh);
// Eq. 1's Delta(v_i) = sum_j (cot a_ij + cot b_ij)(v_j - v_i) at one vertex, from its own faces.
Eigen::Vector3d cotangentLaplace(const TriMesh& mesh, int vertex);

// Those two of one vertex, from its own faces.
double vertexArea(const TriMesh& mesh, int vertex);
Eigen::Vector3d areaWeightedNormal(const TriMesh& mesh, int vertex);

// All three of one vertex in one pass over its faces (Eq. 1's signal and its area), each bit for
// bit what cotangentLaplace, areaWeightedNormal and vertexArea give.
struct VertexGeometry {
  Eigen::Vector3d laplace;
  Eigen::Vector3d normal;
  double area = 0.0;
};
VertexGeometry vertexGeometry(const TriMesh& mesh, int vertex);

// The mesh's points as an n x 3 matrix, one row per vertex.
Eigen::MatrixX3d pointMatrix(const TriMesh& mesh);

// What the EMD nodes read of a whole mesh: cotangentLaplacian(mesh), and each vertex's
// areaWeightedNormal and vertexArea (bit for bit what those give).
struct MeshDifferentials {
  Eigen::SparseMatrix<double> laplacian;
  std::vector<Eigen::Vector3d> normals;
  Eigen::VectorXd areas;
};
MeshDifferentials meshDifferentials(const TriMesh& mesh);

class Context;
// meshDifferentials of a mesh a node's input holds, as derived data (Context::derivedFrom): the
// target's signal and every dab's system on it share one computation.
std::shared_ptr<const MeshDifferentials> derivedMeshDifferentials(Context& ctx,
                                                                  const MeshPtr& mesh);

// How the rebuilt points V^ of a region follow a target T for its Laplacian coordinates, pulled
// towards the original points V by M = diag(mu):
enum class LaplacianForm {
  screened,      // (L + M) V^ = T + M V: L V^ - T = -M (V^ - V), one 1-ring factor (ours)
  leastSquares,  // (L^T L + M^2) V^ = L^T T + M^2 V: min |L V^ - T|^2 + |M (V^ - V)|^2 (Eq. 8)
};

// The system of EMD detail transfer Eqs. 6-8 over a region Q of a mesh, factored. L is Eq. 7's
// cotangent Laplacian restricted to Q, N the original normals, C the fixed outside neighbours'
// share of L V; the signal g^ sets T = -diag(g^) N - C. The matrix is factored once per region and
// mu: a new signal only changes the right-hand side, so moving a gain costs one back-substitution.
class LaplacianSystem final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.LaplacianSystem";
  using Sparse = Eigen::SparseMatrix<double>;
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override { return key; }
  std::string summary() const override;

  MeshPtr mesh;                 // the mesh whose region moves
  Hash meshHash = 0;            // its geometryHash (vertex_fields.hpp), to check fields against
  std::vector<int> vertices;    // Q: the unknowns' mesh vertices, ascending
  std::vector<int> boundary;    // positions in `vertices` on the region's border (mu_boundary)
  Sparse laplacian;             // L: rows and columns the unknowns
  Eigen::MatrixX3d fixedShare;  // C: per unknown, what the fixed vertices outside add to (L V)
  // Per unknown, the original's (L V + C) less its component along the normal: what a target
  // that keeps the surface's tangential Laplacian coordinates adds to -diag(g^) N.
  Eigen::MatrixX3d tangential;
  Eigen::MatrixX3d normals;  // N: per unknown, the original unit normal
  Eigen::MatrixX3d points;   // V: per unknown, the original point
  Eigen::VectorXd mu;        // per unknown
  Eigen::VectorXd area;      // A_i per unknown, for signals given per unit area
  LaplacianForm form = LaplacianForm::screened;
  std::shared_ptr<const Eigen::SimplicialLDLT<Sparse>> factor;  // of L + M or L^T L + M^2
  Hash key = 0;  // of the mesh's geometry, the region and the options
};
using LaplacianSystemPtr = std::shared_ptr<const LaplacianSystem>;

}  // namespace geobrush
