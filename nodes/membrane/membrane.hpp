// The offset membrane of GeoBrush (paper section 4.4, Eqs. 4-5): the C1 biharmonic blend
// x~ : Q -> R^3 on a regular grid over the painted region Q of the parameter domain.
//
// Discretization. A grid of width x height nodes, row-major (node (x, y) is entry
// y * width + x of every per-node array). The grid spacing cancels out of both equations below
// (they are homogeneous), so it is not part of the problem: the caller samples its boundary data
// at the node positions it chose. Every node plays one role (classifyMembraneNodes):
//  - unknown: inside Q (`inside` is nonzero there);
//  - fixed: outside Q but read by the stencil of an unknown node; it carries its channel values;
//  - unused: everything else; its values are never read.
// With MembraneContinuity::C1 (the default, Eq. 4 with the derivative constraints of Eq. 5) the
// unknowns satisfy the 13-point discrete biharmonic equation Delta_h^2 f = 0, and the fixed nodes
// are the two rings outside Q (every node within taxicab distance 2 of Q): the caller samples
// R_out - g_in there, and the two rings carry both the value and the slope across the boundary
// (a first-order encoding of the paper's (f, g) pair; the answer differs from the appendix's form
// at O(h)). With MembraneContinuity::C0 (the paper's Fig. 10 comparison without derivative
// constraints) the unknowns satisfy the 5-point Laplace equation Delta_h f = 0 with one fixed ring
// (the 4-neighbours of Q): C0 only. Q may have any number of boundary loops and holes; it must
// stay two nodes away from the array border so that both rings exist.
//
// Solvers. solveMembrane runs conjugate gradients preconditioned by one V-cycle of a Galerkin
// multigrid: coarse operators R A P with P the cubic B-spline subdivision masked to Q and
// R = P^T (49-point coarse stencils, the rows near the boundary of Q computed one by one), a
// Chebyshev smoother plus Gauss-Seidel sweeps on a band along the boundary of Q, the coarsest level
// (at most ~100 unknowns) solved densely, the cycle in single precision. CG needed 4 to 9
// iterations to 1e-6 on discs, squares, annuli, notched and two-component regions and 2-node-wide
// channels from 64^2 to 256^2, and a warm start from the previous dab's solution one to three.
// The solve and its hierarchy run on a window of the grid around Q (its bounding box with the
// fixed rings and a margin, or the previous hierarchy's window while that holds them): a brush's
// Q covers a few percent of its grid, and the cost follows Q, not the grid.
// solveMembraneDirect solves the same linear system with a sparse LDL^T factorization: the exact
// reference. The paper's appendix iteration (plain damped Richardson, ~N^4 iterations) is not
// implemented.
//
// Kernels. The cycle's stencil work runs on the CPU (vectorized loops) or, with
// MembraneKernel::Vulkan, as Vulkan compute passes (shaders/membrane_level.comp): the Chebyshev
// smoother and the residual of the finest level and of the coarse levels large enough to pay for
// a round trip (MembraneOptions::vulkanMinUnknowns). The band Gauss-Seidel sweeps (a
// sequential recurrence), the transfers between levels, the coarsest dense solve and CG in
// double stay on the CPU, so every smoothed level is one round trip to the device per kernel.
// Both kernels run in single precision; they round differently, and CG reaches the same solution
// with either.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace geobrush {

enum class MembraneContinuity {
  C1,  // Delta^2 f = 0, value and slope fixed: two fixed rings
  C0,  // Delta f = 0, value fixed: one fixed ring
};

enum class MembraneNode : std::uint8_t { Unused, Fixed, Unknown };

// Where the multigrid cycle's stencil kernels run (see "Kernels" above).
enum class MembraneKernel {
  Cpu,
  Vulkan,  // the shared Vulkan device (gpu::VulkanContext), whatever its type
};

struct MembraneProblem {
  int width = 0;
  int height = 0;
  // Q: nonzero at the unknown nodes; width * height entries.
  std::vector<std::uint8_t> inside;
  // One field per channel (x~, y~, z~ for the paper's offsets), width * height values each: the
  // boundary data at the fixed nodes. Values at unknown and unused nodes are ignored.
  std::vector<std::vector<double>> channels;
  MembraneContinuity continuity = MembraneContinuity::C1;
};

// The role of every node of a width x height grid with region `inside`; the fixed nodes are where
// the caller has to provide values. Throws std::invalid_argument as solveMembrane does for a bad
// grid or region.
std::vector<MembraneNode> classifyMembraneNodes(int width, int height,
                                                const std::vector<std::uint8_t>& inside,
                                                MembraneContinuity continuity);

// The multigrid hierarchy of one region Q: built from the mask alone, so successive solves on an
// unchanged Q (other channels, other boundary data, the next frame) share it. Opaque; thread-safe
// to share between concurrent solves.
class MembraneHierarchy;

struct MembraneMultigridSettings {
  // Degree of the Chebyshev polynomial in each pre- and post-smoothing step.
  int smootherDegree = 3;
  // The smoother damps the eigenvalues of D^-1 A in [lambdaMax / smootherRatio, lambdaMax].
  double smootherRatio = 16;
  // Gauss-Seidel sweeps on the unknowns within `bandWidth` nodes of the boundary of Q, where the
  // Galerkin coarse levels approximate the operator worst.
  int bandWidth = 3;
  int bandSweeps = 1;
  // Cycles on each coarse level per visit: 1 is a V-cycle, 2 a W-cycle (fewer CG iterations,
  // each about twice as expensive: slower here).
  int coarseCycles = 1;
  // Coarsening stops at a level with at most this many unknowns, which is solved densely.
  int coarsestUnknowns = 100;
};

struct MembraneOptions {
  // Stop at the first iterate whose estimated energy-norm error is at most `tolerance` of the
  // solution's: r.Mr <= tolerance^2 b.x per channel, M the multigrid preconditioner (see
  // conjugateGradients in membrane.cpp). On the 64^2-256^2 test regions at 1e-6 the largest error
  // at a node stayed below 1e-4 of the solution's magnitude from a cold start, a warm start after
  // a dab, and rough boundary data alike.
  double tolerance = 1e-6;
  int maxIterations = 100;
  // Empty: a nested-iteration (full multigrid) start on the hierarchy. Else one field per
  // channel (width * height values; read at the unknown nodes only), e.g. the previous dab's
  // solution.
  std::vector<std::vector<double>> initialGuess;
  // Reused when it was built for the same region, window, continuity and settings
  // (MembraneResult::hierarchyReused). Otherwise a new one is built; when only the region
  // differs (the next dab) and its window still holds the region, it copies the coarse rows
  // that the change did not reach, which makes it several times faster to build and no
  // different.
  std::shared_ptr<const MembraneHierarchy> hierarchy;
  MembraneMultigridSettings multigrid;
  // Threads solving the channels side by side (each channel on one thread) and sharing the rows
  // of a new hierarchy's coarse levels; 0 picks the hardware's. The hierarchy and the values are
  // bit-identical for every thread count.
  int threads = 0;
  // Vulkan: the device kernels are made on the hierarchy's first Vulkan solve and kept with it,
  // so its coefficients are uploaded once. Deterministic on one device, but not bit-identical to
  // the CPU kernel (within the tolerance of it).
  MembraneKernel kernel = MembraneKernel::Cpu;
  // With the Vulkan kernel, coarse levels with fewer unknowns than this run on the CPU all the
  // same: a round trip to the device (submission, fence, readback) costs tens of microseconds on
  // any device, the CPU kernel about a nanosecond per unknown and step. The finest level always
  // runs on the device.
  int vulkanMinUnknowns = 4096;
};

struct MembraneChannelReport {
  int iterations = 0;
  double residual = 0;  // relative, ||b - A x|| / ||b|| (0 when b = 0)
  bool converged = false;
};

struct MembraneResult {
  // The channels with the unknown nodes solved; the other nodes keep the problem's values.
  std::vector<std::vector<double>> values;
  std::vector<MembraneChannelReport> channels;
  int iterations = 0;      // the most any channel took
  double residual = 0;     // the largest relative residual of any channel
  bool converged = false;  // every channel reached the tolerance within maxIterations
  std::shared_ptr<const MembraneHierarchy> hierarchy;  // pass back in MembraneOptions to reuse
  bool hierarchyReused = false;
  int levels = 0;  // multigrid levels, the finest included
  int unknowns = 0;
  MembraneKernel kernel = MembraneKernel::Cpu;  // the kernel that ran (the options')
  int vulkanLevels = 0;  // levels whose smoother and residual ran on the Vulkan device
};

// Solves the membrane for every channel (Eqs. 4-5 discretized as described above). A channel that
// does not reach the tolerance within maxIterations, or whose iteration breaks down, is reported
// with converged = false and the best iterate reached. Throws std::invalid_argument for a grid
// smaller than 5 x 5 or larger than 2^28 nodes, a wrong array size, an empty Q, Q within two nodes
// of the array border, no channels, a non-finite fixed value or initial guess, a channel count of
// the initial guess different from the problem's, a non-positive tolerance or negative
// maxIterations or vulkanMinUnknowns, or bad multigrid settings; std::runtime_error for the Vulkan
// kernel when no Vulkan device exists or a Vulkan call fails.
MembraneResult solveMembrane(const MembraneProblem& problem, const MembraneOptions& options = {});

struct MembraneDirectResult {
  std::vector<std::vector<double>> values;  // as MembraneResult::values
  double residual = 0;                      // the largest relative residual of any channel
};

// The same discrete system assembled as a sparse matrix and solved by Eigen's SimplicialLDLT:
// the exact reference for solveMembrane (seconds at 512^2). Throws as solveMembrane does, and
// std::runtime_error when the factorization fails.
MembraneDirectResult solveMembraneDirect(const MembraneProblem& problem);

// ||b - A x|| / ||b|| for each channel, with x read from `values` at the unknown nodes (where
// b = 0: ||A x||). Throws as solveMembrane does for a bad problem or mismatched `values`.
std::vector<double> membraneResidual(const MembraneProblem& problem,
                                     const std::vector<std::vector<double>>& values);

}  // namespace geobrush
