// The common parameterization of a feature F and its base B (topology-free cut and paste,
// ../shared/papers/topology-free-cut-and-paste.txt, Sec. 6.1): both are mapped to the plane by
// Desbrun, Meyer and Alliez's intrinsic parameterization ("Intrinsic parameterizations of surface
// meshes", 2002), a blend of the discrete conformal (Dirichlet) and authalic (chi) maps, with the
// same boundary: F's boundary vertex F.boundary[i] and B's vertex i get the same uv, so that P^F
// and P^B cover the same region of the plane.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// Where the boundary's uv comes from.
enum class BoundaryMode {
  Plane,       // the boundary projected onto its best-fit plane
  Natural,     // B flattened with a free boundary (LSCM)
  ConvexHull,  // the convex hull of the natural boundary
  Auto,        // Plane, or ConvexHull where P^F leaves P^B's boundary
};

struct IntrinsicParamOptions {
  double lambda = 0.5;  // weight of the Dirichlet (conformal) energy
  double mu = 0.5;      // weight of the chi (authalic) energy
  BoundaryMode boundary = BoundaryMode::Auto;
  // When set, both uv sets are moved by the similarity that best maps F's boundary uv onto this
  // parameterization's uv of the same source vertices, and take its origin, rotation and scale.
  const Parameterization* frame = nullptr;
};

// A bad input; `port` names it ("feature", "base" or "frame").
class IntrinsicParamError : public std::runtime_error {
 public:
  IntrinsicParamError(std::string port, const std::string& message)
      : std::runtime_error(message), port_(std::move(port)) {}
  const std::string& port() const { return port_; }

 private:
  std::string port_;
};

// A plane fitted to points: (uAxis, vAxis, normal) right-handed.
struct PlaneFit {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d uAxis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d vAxis = Eigen::Vector3d::UnitY();
  Eigen::Vector2d project(const Eigen::Vector3d& p) const {
    return {(p - centroid).dot(uAxis), (p - centroid).dot(vAxis)};
  }
};

struct IntrinsicParamResult {
  std::vector<Eigen::Vector2d> featureUv;      // per F surface vertex
  std::vector<Eigen::Vector2d> baseUv;         // per B vertex
  std::vector<Eigen::Vector3d> featureNormal;  // per F surface vertex, unit, from F's source mesh
  std::vector<Eigen::Vector3d> baseNormal;     // per B vertex, unit
  std::vector<std::uint8_t> featureFlipped;    // per F face: 1 where its uv triangle is clockwise
  std::vector<std::uint8_t> baseFlipped;       // per B face: the same
  PlaneFit plane;                              // of F's boundary
  // Without a frame: at the plane's centroid with its axes, rotation 0, scale 1; with one, the
  // frame's.
  Frame origin;
  double rotation = 0;
  double scale = 1;
  BoundaryMode used = BoundaryMode::Plane;  // Auto resolved
  int outsideVertices = 0;       // interior F vertices whose uv lies outside P^B's boundary polygon
  int planeOutsideVertices = 0;  // the same under Plane, where Auto switched to ConvexHull
  bool planeOutlineCrosses = false;  // Plane's outline crossed itself, where Auto switched
};

// Throws IntrinsicParamError unless B keeps the pipeline's convention over F (cut_paste.hpp):
// B's vertices 0..n-1 at F.boundary's positions (within 1e-9 of F's diagonal), met in that order
// along B's one boundary loop. Returns B's boundary loop from vertex 0.
std::vector<int> checkBaseConvention(const Canvas& feature, const TriMesh& base);

// The paper's Sec. 6.1 with Desbrun et al.'s Eq. (intrinsic map) for the interior.
IntrinsicParamResult intrinsicParameterize(const Canvas& feature, const TriMesh& base,
                                           const IntrinsicParamOptions& options);

// Stages, exposed for tests.

// The least-squares plane of `loop` (PCA: the normal is the smallest eigenvector), its normal
// turned so that a loop run like boundary halfedges (against the faces) is clockwise about it,
// i.e. the faces are counter-clockwise in (u, v).
PlaneFit fitBoundaryPlane(const std::vector<Eigen::Vector3d>& loop);

// Desbrun et al.'s intrinsic map (lambda M^A + mu M^chi): every vertex with fixed[v] == 0 solves
// sum_j [lambda (cot a_ij + cot b_ij) + mu (cot g_ij + cot d_ij) / |x_i - x_j|^2] (u_i - u_j) = 0
// (a, b opposite edge ij; g, d at x_j, as in CGAL's Discrete_authalic_parameterizer_3); the
// others keep `uv`. Throws IntrinsicParamError(port, ...) for degenerate faces or a singular
// system.
std::vector<Eigen::Vector2d> solveIntrinsic(const TriMesh& mesh, const std::vector<char>& fixed,
                                            std::vector<Eigen::Vector2d> uv, double lambda,
                                            double mu, const std::string& port);

// Lévy, Petitjean, Ray and Maillot's least squares conformal map (2002: each triangle's
// conformality in complex form, Sec. 3), pinA at (0, 0) and pinB at
// (|x_pinB - x_pinA|, 0): the natural boundary the paper asks of P^B.
std::vector<Eigen::Vector2d> leastSquaresConformalMap(const TriMesh& mesh, int pinA, int pinB,
                                                      const std::string& port);

// The paper's Sec. 6.1 convex hull boundary: the loop's convex hull (its vertices stay), the
// loop's other points moved onto the hull edge between the hull vertices before and after them,
// at their share of the loop's length between those two (ours). The loop may run either way.
std::vector<Eigen::Vector2d> placeOnConvexHull(const std::vector<Eigen::Vector2d>& loop);

// Ours (spec 2.2, shared (u, v) domain): the similarity (core fitSimilarity2d) from F's boundary uv
// to `frame`'s uv at the same source vertices. Throws IntrinsicParamError("frame", ...) with fewer
// than 3 matches or a frame on another mesh.
Eigen::Matrix3d frameAlignment(const Canvas& feature, const std::vector<Eigen::Vector2d>& featureUv,
                               const Parameterization& frame);

}  // namespace geobrush
