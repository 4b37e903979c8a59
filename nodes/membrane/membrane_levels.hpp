// Internals of the membrane solver (GeoBrush paper section 4.4): the padded grid layout, the
// levels of the Galerkin multigrid and the kernels that apply their operators.
#pragma once

#include <Eigen/Dense>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "membrane.hpp"

namespace geobrush::membrane_detail {

class VulkanCycleKernels;  // membrane_vulkan.hpp

// Stencils reach at most three nodes each way (the finest level's 13-point plate two, the
// 49-point Galerkin coarse operators three). Unknowns are at least one node inside every level's
// grid, and a margin of three nodes around it lets the kernels (stencils and the transfers'
// B-spline windows) skip bounds checks. Vectors are zero on the margin and everywhere off the
// unknowns.
constexpr int kReach = 3;
constexpr int kPad = 3;
constexpr int kStencilSide = 2 * kReach + 1;
constexpr int kSlots = kStencilSide * kStencilSide;
using Stencil = std::array<double, kSlots>;
constexpr int stencilSlot(int dx, int dy) {
  return (dy + kReach) * kStencilSide + dx + kReach;
}

// A rectangle of nodes of a problem's grid: the part of it a hierarchy lies on.
struct GridWindow {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool contains(const GridWindow& other) const {
    return other.x >= x && other.y >= y && other.x + other.width <= x + width &&
           other.y + other.height <= y + height;
  }
  bool operator==(const GridWindow&) const = default;
};

struct PaddedGrid {
  int width = 0;
  int height = 0;
  int stride() const { return width + 2 * kPad; }
  int rows() const { return height + 2 * kPad; }
  std::size_t size() const { return std::size_t(stride()) * std::size_t(rows()); }
  int index(int x, int y) const { return (y + kPad) * stride() + x + kPad; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

// How the regular stencil is applied: written out for the finest level's, 49 taps on coarse
// levels.
enum class StencilShape { Plate, Laplace, Full };

// A row of a coarse operator that differs from the level's regular stencil: near the boundary of
// Q the masked prolongation cuts the Galerkin product short.
struct CustomRow {
  int node;
  Stencil weights;
};

// Padded indexes [begin, end) of one grid row that hold all of its unknowns (begin == end: none).
struct RowSpan {
  int begin = 0;
  int end = 0;
};

// The coefficients in single precision, which the multigrid cycle runs in: it only has to
// precondition, and floats halve its memory traffic and double its SIMD width. The conjugate
// gradients around it, the residuals they test and the setup stay in double.
// A custom row for the CPU kernels: each stencil row padded to eight weights (the eighth zero),
// so that a row of the stencil is one vector multiply.
constexpr int kPaddedSide = 8;
using PaddedStencil = std::array<float, kStencilSide * kPaddedSide>;

struct SingleCoefficients {
  std::vector<float> mask;
  std::vector<float> inverseDiagonal;
  std::array<float, kSlots> regular{};
  std::vector<std::array<float, kSlots>> custom;  // parallel to Level::customRows
  std::vector<PaddedStencil> customPadded;        // the same, padded
};

struct Level {
  PaddedGrid grid;
  std::vector<double> mask;   // 1 at the unknowns, else 0
  std::vector<int> unknowns;  // padded indexes, ascending
  int activeBegin = 0;  // [activeBegin, activeEnd): the padded indexes from first to last unknown
  int activeEnd = 0;
  std::vector<RowSpan> spans;  // one per grid row
  Stencil regular{};
  bool mirrored = false;  // the regular stencil is even in dx and in dy (exactly)
  StencilShape shape = StencilShape::Full;
  int reach = kReach;                     // of the regular stencil and every custom row
  std::array<int, kSlots> slotOffsets{};  // padded-array offset of every stencil slot
  std::vector<CustomRow> customRows;      // ascending by node
  std::vector<int> customBegin;   // per grid row, first entry of customRows in it; one past the end
  std::vector<int> customOfNode;  // index into customRows, -1 for regular rows
  std::vector<double> inverseDiagonal;  // 0 off the unknowns
  std::vector<int> band;                // unknowns near the boundary of Q, ascending
  double lambdaMax = 0;                 // an upper bound of the eigenvalues of D^-1 A
  SingleCoefficients single;
};

// The dense factorization of the coarsest level. Its operator is singular where the region is
// thinner than the level's spacing (cut to the few fine unknowns they cover, the B-splines of
// neighbouring coarse nodes become linearly dependent): the pivoted LDL^T of a semidefinite matrix
// then ends in pivots at round-off level, and the solve drops them, acting as a symmetric
// pseudo-inverse.
struct CoarsestSolver {
  std::vector<int> nodes;  // the level's unknowns
  Eigen::LDLT<Eigen::MatrixXd> factorization;
  double pivotTolerance = 0;
};

// The kernels, in double (the conjugate gradients) and float (the multigrid cycle). Vectors are
// padded arrays, zero off the level's unknowns.
// out = A x over the level's unknowns, zero elsewhere.
void applyOperator(const Level& level, const double* x, double* out);
void applyOperator(const Level& level, const float* x, float* out);
// out = base - A x over the level's unknowns, zero elsewhere; out may alias base (not x).
void subtractOperator(const Level& level, const double* base, const double* x, double* out);
void subtractOperator(const Level& level, const float* base, const float* x, float* out);
// One step of the Chebyshev smoother's three-term recurrence: r = b - A x,
// d = keep d + gain D^-1 r, xNext = x + d. xNext must not alias x.
void chebyshevStep(const Level& level, const float* b, const float* x, float* xNext, float* d,
                   float keep, float gain);
// The dot product over the level's unknowns (the spans), in four interleaved sums: vectorized, and
// in the same order on every machine and run.
double dotProduct(const Level& level, const double* a, const double* b);
// q = A p (as applyOperator) and returns p . q, summed as dotProduct does.
double applyOperatorDot(const Level& level, const double* p, double* q);
// x += alpha p, r -= alpha q over the level's unknowns; returns r . r, summed as dotProduct does.
double updateResidual(const Level& level, double alpha, const double* p, const double* q, double* x,
                      double* r);
// (A x) at one unknown node.
double rowProduct(const Level& level, const double* x, int node);
float rowProduct(const Level& level, const float* x, int node);
// Gauss-Seidel sweeps over the level's band: x += D^-1 (b - A x) node by node, in ascending order
// (forward) or descending.
void sweepBand(const Level& level, const float* b, float* x, bool forward, int sweeps);
// R r: the transpose of the masked B-spline prolongation.
void restrictToCoarse(const Level& fine, const Level& coarse, const double* fineValues,
                      double* coarseValues);
void restrictToCoarse(const Level& fine, const Level& coarse, const float* fineValues,
                      float* coarseValues);
// fine += P coarse, masked to the fine unknowns.
void prolongAdd(const Level& coarse, const Level& fine, const double* coarseValues,
                double* fineValues);
void prolongAdd(const Level& coarse, const Level& fine, const float* coarseValues,
                float* fineValues);

// The finest level: the plate (13-point) or Laplace (5-point) stencil on the unknowns of Q.
Level finestLevel(int width, int height, const std::vector<std::uint8_t>& inside,
                  MembraneContinuity continuity, int bandWidth);
// The Galerkin coarse level R A P of `fine`. With `previous`, the same coarse level of a previous
// region on the same grid, rows out of reach of the `fineChanged` nodes (see changedNodes) are
// copied from it: the result is the same, bit for bit. The rows are computed on up to `threads`
// threads (0: the hardware's), with the same result for any count.
Level coarsenLevel(const Level& fine, int bandWidth, const Level* previous = nullptr,
                   const std::vector<std::uint8_t>* fineChanged = nullptr, int threads = 1);
// Marks the nodes whose mask or operator row differ between two versions of a level.
std::vector<std::uint8_t> changedNodes(const Level& now, const Level& before);
CoarsestSolver factorCoarsest(const Level& level);
// x = A^+ b on the coarsest level, solved in double; `scratch` holds the gathered unknowns.
void solveCoarsest(const CoarsestSolver& solver, const float* b, float* x,
                   Eigen::VectorXd& scratch);

// Checks the problem (see solveMembrane) and returns the role of every node.
std::vector<MembraneNode> validateProblem(const MembraneProblem& problem);
// A row-major field copied into the padded layout at the nodes of one role, zero elsewhere.
std::vector<double> padded(const PaddedGrid& grid, const std::vector<double>& field,
                           const std::vector<MembraneNode>& roles, MembraneNode role);
// The row-major indexes of the nodes of one role, ascending.
std::vector<int> nodesOf(const std::vector<MembraneNode>& roles, MembraneNode role);
// As padded, at the row-major `nodes` (e.g. nodesOf one role).
std::vector<double> padded(const PaddedGrid& grid, const std::vector<double>& field,
                           const std::vector<int>& nodes);
// b = -A_IB f_B on the finest level's unknowns from the padded fixed values.
std::vector<double> rightHandSide(const Level& finest, const std::vector<double>& fixedValues);

}  // namespace geobrush::membrane_detail

namespace geobrush {

class MembraneHierarchy {
 public:
  // `previous`, a hierarchy of another region on the same grid, saves recomputing what the
  // change of region did not reach. `threads` (0: the hardware's) share the coarse rows; the
  // hierarchy is the same for any count.
  MembraneHierarchy(int width, int height, std::vector<std::uint8_t> inside,
                    MembraneContinuity continuity, const MembraneMultigridSettings& settings,
                    const MembraneHierarchy* previous = nullptr, int threads = 1);

  bool fits(const MembraneProblem& problem, const MembraneMultigridSettings& settings) const;
  // Where the hierarchy's grid lies on the grid of the problems it was made for (solveMembrane
  // solves on a window around Q), and that grid's size: the whole grid unless set.
  const membrane_detail::GridWindow& window() const { return window_; }
  int problemWidth() const { return problemWidth_; }
  int problemHeight() const { return problemHeight_; }
  void placeOn(const membrane_detail::GridWindow& window, int problemWidth, int problemHeight) {
    window_ = window;
    problemWidth_ = problemWidth;
    problemHeight_ = problemHeight;
  }
  const std::vector<membrane_detail::Level>& levels() const { return levels_; }
  const membrane_detail::CoarsestSolver& coarsest() const { return coarsest_; }
  // The Vulkan kernels of the levels, made on the first call and kept with the hierarchy, so that
  // every solve on it shares one upload of the coefficients. Thread-safe. Throws
  // std::runtime_error without a Vulkan device. Defined in membrane_vulkan.cpp. They hold device
  // buffers: a hierarchy that made them must not outlive the Vulkan context, which static
  // destruction ends at exit (do not keep one in a static made before the context).
  membrane_detail::VulkanCycleKernels& vulkanKernels() const;

 private:
  struct VulkanCache {
    std::mutex mutex;
    std::shared_ptr<membrane_detail::VulkanCycleKernels> kernels;  // null until first used
  };

  int width_;
  int height_;
  membrane_detail::GridWindow window_{0, 0, width_, height_};
  int problemWidth_ = width_;
  int problemHeight_ = height_;
  std::vector<std::uint8_t> inside_;  // as given: any nonzero value marks Q
  MembraneContinuity continuity_;
  int bandWidth_;
  int coarsestUnknowns_;
  std::vector<membrane_detail::Level> levels_;
  membrane_detail::CoarsestSolver coarsest_;
  std::unique_ptr<VulkanCache> vulkan_ = std::make_unique<VulkanCache>();
};

}  // namespace geobrush
