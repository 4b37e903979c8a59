// Variational paste: the GeoBrush paper's Eq. 3 (section 4.4), min ∫‖Δx − δ_in‖² with x = R_out
// in value and slope on ∂Ω, solved on the irregular stitched mesh with Ceres instead of the offset
// membrane on the grid: the slow, exact reference the membrane is compared against.
//
// Topology. stitchPaste with x~ = 0 gives the result mesh (the target with R_in at G and the seam
// strips) and its PasteMap. The pasted vertices are the unknowns; every other vertex keeps its
// target position. The fixed vertices next to an unknown (ring 1) carry the positional
// constraint; their own fixed neighbours (ring 2) enter through ring 1's Laplacians and carry
// the slope (the tangent constraint), as two fixed rings do for the membrane.
//
// Discretization. L(x)_v = x_v − Σ_w λ_vw x_w over v's one-ring in the result mesh, with
// Floater's mean-value weights λ computed in the shared parameter domain (each vertex at its uv:
// source uv for pasted vertices, target uv for fixed ones). The energy is
// E(x) = Σ_v ‖L(x)_v − δ_v‖² over the unknowns and ring 1, whose minimizer solves the discrete
// bi-Laplacian LᵀL x = Lᵀδ of Eq. 3 with both rings fixed. δ_v = L(g)_v is the Laplacian, with
// the same operator on the same mesh, of the draft g: at a pasted vertex its draft position G(v),
// at a fixed vertex of rings 1-2 the draft sampled at that vertex's target uv, G(E_s^-1(E_t(w)))
// (barycentric on the source canvas). So at a pasted vertex away from the seam δ_v is the
// draft's Laplacian over its source-canvas one-ring (δ_in = Δg_in), and E = Σ ‖L(x − g)‖²: the
// offset x − g is the discrete biharmonic function equal to R_out − g_in on both rings, the
// membrane's Eq. 4 posed on the mesh. An exact draft (G = the target surface) has zero energy at
// x = the target.
// The draft is read only on R_in and the region's draft support, all that a warp of the region
// moves (the rest stays at its source positions: in a clone, on the source mesh). A ring vertex
// whose source triangle reaches past the support (a target coarser than the region's grid) gets
// R_out(w) plus the draft's detail over the target, G − E_t^-1, extended affinely in (u, v) from
// the nearest supported vertices; read there, the unwarped draft made the mountain clone onto a
// sphere a spike 12 times the paste's size.
// Why mean-value weights: they are fixed (independent of x, so Eq. 3 stays linear), positive on
// any fan, also on the seam strips' long thin triangles where cotangents blow up or turn
// negative, and they have linear precision in (u, v): an offset affine in the domain has zero
// Laplacian, as on the membrane's grid. The uniform graph Laplacian (LaplacianWeights::Uniform)
// lacks that on the irregular seam strips: there the biharmonic offset kinks, and the seam's
// normal jump was 3.4 times the mean-value result's in the bowl test (p95 10.4 against 3.1
// degrees, the target's own 3.1).
//
// Rotation-invariant mode. Each vertex v of the energy gets a local rotation R_v (angle-axis, 3
// unknowns) that turns its Laplacian coordinate, and a ring-fit term ties R_v to how v's one-ring
// edges turned from the draft:
//   E = Σ_v ‖L(x)_v − R_v δ_v‖² + s² Σ_v Σ_(w ∈ N(v)) ‖(x_w − x_v) − R_v (g_w − g_v)‖²,
// s = rotationWeight · RMS|δ| / RMS draft edge length. A rotation-smoothness term between
// neighbours alone is not enough: L has linear precision, so a detail sheared whole keeps its
// Laplacians up to a common rotation and would cost nothing; the ring fit makes the rotation that
// of the local geometry, as Sorkine et al.'s implicit transformations do. A draft whose detail
// is turned against the target (a badly fitted cage) then keeps its shape instead of being
// sheared. Solved by Levenberg-Marquardt from the linear solution with every R_v = I; where the
// offset is a rigid motion the ring-fit term vanishes and both modes agree.
//
// Solver. Ceres, SPARSE_NORMAL_CHOLESKY (CHOLMOD). Each unknown coordinate is its own scalar
// parameter block and each Laplacian residual one row per coordinate, so that the linear mode's
// normal equations are three decoupled bi-Laplacians (no 3 x 3 block fill).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include "geobrush/canvas.hpp"
#include "geobrush/region.hpp"
#include "geobrush/stitch.hpp"

namespace geobrush {

// The inputs do not fit together (draft and source canvas, region and canvases), or the stitch
// fails: the message says which.
class VariationalPasteError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The solver stopped without converging, was cancelled, or produced non-finite positions. The
// message carries Ceres' reason.
class VariationalPasteSolveError : public std::runtime_error {
 public:
  VariationalPasteSolveError(const std::string& message, bool cancelled)
      : std::runtime_error(message), cancelled_(cancelled) {}
  bool cancelled() const { return cancelled_; }

 private:
  bool cancelled_;
};

// The weights of the Laplacian L (see the header comment).
enum class LaplacianWeights {
  MeanValue,  // Floater's mean-value weights in the parameter domain: linear precision in (u, v)
  Uniform,    // 1 / valence: the graph Laplacian
};

struct VariationalPasteOptions {
  LaplacianWeights weights = LaplacianWeights::MeanValue;
  bool rotationInvariant = false;
  // The weight of the ring-fit term that ties each rotation to its one-ring, relative to the
  // Laplacian term (see the header comment): larger makes the paste stiffer (as-rigid-as-possible)
  // against the offset, smaller lets the rotations follow δ more freely.
  double rotationWeight = 1.0;
  // Levenberg-Marquardt iterations at most, per solve (the rotation-invariant mode's linear start
  // is a solve of its own).
  int maxIterations = 100;
  // Ceres' function tolerance: converged when an iteration lowers the energy by less than this
  // fraction of it.
  double tolerance = 1e-10;
  // Ceres' threads for evaluating the residuals. 1 by default: with more, the energy and gradient
  // are summed in an order that depends on scheduling, and the result may differ in the last bits.
  int threads = 1;
  // Polled once per iteration; returning true stops the solve with a cancelled
  // VariationalPasteSolveError.
  std::function<bool()> cancelled;
  // Called once per iteration with the share of the iteration budget spent: the linear solve
  // takes [0, 0.5), the rotation-invariant one [0.5, 1).
  std::function<void(double)> progress;
};

struct VariationalPasteReport {
  std::size_t unknownVertices = 0;  // pasted vertices: 3 unknowns each
  std::size_t ringVertices = 0;     // fixed vertices whose Laplacian is in the energy (ring 1)
  std::size_t rotations = 0;        // local rotations (rotation-invariant mode)
  int linearIterations = 0;         // Ceres iterations of the linear solve
  int rotationIterations = 0;       // Ceres iterations of the rotation-invariant solve
  double initialEnergy = 0;         // E at the draft (x = G)
  double finalEnergy = 0;           // E at the result
  std::string solver;               // Ceres' brief report of the last solve
};

struct VariationalPasteResult {
  TriMesh mesh;  // the target with the paste, as stitchPaste's with x~ = 0 but x solved
  PasteMap map;  // stitchPaste's map: the topology is the same
  VariationalPasteReport report;
};

// `draft` is G(P_s) with the source canvas' connectivity; only its vertices in R_in and
// region.draftSupport are read (see the header comment). An empty region gives the target mesh
// unchanged. `base`, when given, must be stitchBase(target). Throws VariationalPasteError when
// the inputs do not fit (see stitchPaste) or a fixed vertex of the two rings lies outside the
// target canvas, and VariationalPasteSolveError when the solve does not converge within
// maxIterations, is cancelled, or gives non-finite positions: no half-solved mesh is returned.
VariationalPasteResult variationalPaste(const Region2D& region, const Parameterization& source,
                                        const TriMesh& draft, const Parameterization& target,
                                        const VariationalPasteOptions& options = {},
                                        const StitchBase* base = nullptr);

}  // namespace geobrush
