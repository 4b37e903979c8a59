// The offset membrane solver (GeoBrush paper section 4.4, Eqs. 4-5): conjugate gradients
// preconditioned by a V-cycle of the Galerkin multigrid built in membrane_levels.cpp.
#include "membrane.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "membrane_levels.hpp"
#include "membrane_vulkan.hpp"

namespace geobrush {
namespace membrane_detail {

namespace {

// The fixed rings outside Q: two for the plate's 13-point stencil. The harmonic mode reads one,
// but asks for the same room, so that one region serves both modes.
constexpr int kRings = 2;

std::string nodeName(int x, int y) {
  std::string name = "(";
  name += std::to_string(x);
  name += ", ";
  name += std::to_string(y);
  name += ")";
  return name;
}

void validateRegion(int width, int height, const std::vector<std::uint8_t>& inside) {
  if (width < 5 || height < 5) {
    std::string message = "membrane: the grid must be at least 5 x 5 nodes, got ";
    message += std::to_string(width);
    message += " x ";
    message += std::to_string(height);
    throw std::invalid_argument(message);
  }
  if (double(width) * double(height) > double(1 << 28))
    throw std::invalid_argument("membrane: the grid has more than 2^28 nodes");
  if (inside.size() != std::size_t(width) * std::size_t(height)) {
    std::string message = "membrane: the region mask has ";
    message += std::to_string(inside.size());
    message += " entries, the grid ";
    message += std::to_string(std::size_t(width) * std::size_t(height));
    throw std::invalid_argument(message);
  }
  // The nodes within kRings of the border, in row-major order (the first one found is named),
  // then the whole mask at once (a branch-free pass).
  for (int y = 0; y < height; ++y) {
    const bool borderRow = y < kRings || y >= height - kRings;
    for (int x = 0; x < width; ++x) {
      if (!borderRow && x == kRings) x = width - kRings;
      if (!inside[std::size_t(y) * std::size_t(width) + std::size_t(x)]) continue;
      std::string message = "membrane: the region reaches node ";
      message += nodeName(x, y);
      message += ", within two nodes of the grid border (the fixed rings need the room)";
      throw std::invalid_argument(message);
    }
  }
  std::uint8_t any = 0;
  for (std::uint8_t flag : inside)
    any |= flag;
  if (any == 0) throw std::invalid_argument("membrane: the region Q is empty (no unknown node)");
}

void validateFields(const std::vector<std::vector<double>>& fields, std::size_t count,
                    std::size_t nodes, const char* what) {
  if (fields.size() != count) {
    std::string message = "membrane: ";
    message += what;
    message += " has ";
    message += std::to_string(fields.size());
    message += " channels, the problem ";
    message += std::to_string(count);
    throw std::invalid_argument(message);
  }
  for (std::size_t c = 0; c < count; ++c)
    if (fields[c].size() != nodes) {
      std::string message = "membrane: channel ";
      message += std::to_string(c);
      message += " of ";
      message += what;
      message += " has ";
      message += std::to_string(fields[c].size());
      message += " values, the grid ";
      message += std::to_string(nodes);
      throw std::invalid_argument(message);
    }
}

// Only the values the solver reads must be finite: the caller need not sample unused nodes.
bool allFinite(const std::vector<std::vector<double>>& fields,
               const std::vector<MembraneNode>& roles, MembraneNode role) {
  // One pass over the nodes for all channels.
  bool finite = true;
  for (std::size_t i = 0; i < roles.size(); ++i)
    if (roles[i] == role)
      for (const std::vector<double>& field : fields)
        finite = finite && std::isfinite(field[i]);
  return finite;
}

// Throws for the first channel's first node of `role` whose value is not finite.
void requireFinite(const std::vector<std::vector<double>>& fields,
                   const std::vector<MembraneNode>& roles, MembraneNode role, const char* what) {
  if (allFinite(fields, roles, role)) return;
  for (std::size_t c = 0; c < fields.size(); ++c)
    for (std::size_t i = 0; i < roles.size(); ++i)
      if (roles[i] == role && !std::isfinite(fields[c][i])) {
        std::string message = "membrane: ";
        message += what;
        message += " of channel ";
        message += std::to_string(c);
        message += " is not finite at node ";
        message += std::to_string(i);
        throw std::invalid_argument(message);
      }
}

}  // namespace

std::vector<MembraneNode> validateProblem(const MembraneProblem& problem) {
  validateRegion(problem.width, problem.height, problem.inside);
  if (problem.channels.empty())
    throw std::invalid_argument("membrane: the problem has no channels");
  const std::size_t nodes = problem.inside.size();
  validateFields(problem.channels, problem.channels.size(), nodes, "the boundary data");
  std::vector<MembraneNode> roles =
      classifyMembraneNodes(problem.width, problem.height, problem.inside, problem.continuity);
  requireFinite(problem.channels, roles, MembraneNode::Fixed, "the boundary value");
  return roles;
}

std::vector<double> padded(const PaddedGrid& grid, const std::vector<double>& field,
                           const std::vector<MembraneNode>& roles, MembraneNode role) {
  std::vector<double> out(grid.size(), 0.0);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(grid.width) + std::size_t(x);
      if (roles[i] == role) out[std::size_t(grid.index(x, y))] = field[i];
    }
  return out;
}

std::vector<int> nodesOf(const std::vector<MembraneNode>& roles, MembraneNode role) {
  std::vector<int> nodes;
  for (std::size_t i = 0; i < roles.size(); ++i)
    if (roles[i] == role) nodes.push_back(int(i));
  return nodes;
}

std::vector<double> padded(const PaddedGrid& grid, const std::vector<double>& field,
                           const std::vector<int>& nodes) {
  std::vector<double> out(grid.size(), 0.0);
  for (int i : nodes)
    out[std::size_t(grid.index(i % grid.width, i / grid.width))] = field[std::size_t(i)];
  return out;
}

std::vector<double> rightHandSide(const Level& finest, const std::vector<double>& fixedValues) {
  // b = -A_IB f_B: the finest operator's rows at the unknowns are the regular stencil, so applying
  // the level's operator to the fixed values alone (zero at the unknowns) gives A_IB f_B.
  std::vector<double> b(finest.grid.size(), 0.0);
  applyOperator(finest, fixedValues.data(), b.data());
  for (const RowSpan& span : finest.spans)
    for (int i = span.begin; i < span.end; ++i)
      b[std::size_t(i)] = -b[std::size_t(i)];
  return b;
}

}  // namespace membrane_detail

namespace {

using membrane_detail::Level;

double dot(const Level& level, const double* a, const double* b) {
  return membrane_detail::dotProduct(level, a, b);
}

double norm(const Level& level, const double* a) {
  return std::sqrt(dot(level, a, a));
}

// Copies the unknowns' values (row spans; every other node of the level's vectors stays zero).
template <typename From, typename To>
void copyActive(const Level& level, const From* from, To* to) {
  for (const membrane_detail::RowSpan& span : level.spans)
    std::copy(from + span.begin, from + span.end, to + span.begin);
}

// A cycle's vectors on one level, in single precision (see SingleCoefficients).
struct CycleVectors {
  CycleVectors(std::size_t size, bool repeatedCycles)
      : b(size, 0.0f),
        x(size, 0.0f),
        r(size, 0.0f),
        t(size, 0.0f),
        d(size, 0.0f),
        c(repeatedCycles ? size : 0, 0.0f),
        e(repeatedCycles ? size : 0, 0.0f) {}
  std::vector<float> b, x;     // this level's right-hand side and solution within a cycle
  std::vector<float> r, t, d;  // residual, second iterate and step of the smoother
  std::vector<float> c, e;     // right-hand side and solution of a repeated coarse cycle
};

// The Chebyshev smoother's steps on one level: x += p(D^-1 A) D^-1 (b - A x) with the polynomial
// of the settings' degree that is smallest on [lambdaMax / ratio, lambdaMax], one step of the
// three-term recurrence (see chebyshevStep) per degree.
std::vector<membrane_detail::ChebyshevStep> chebyshevSteps(
    const Level& level, const MembraneMultigridSettings& settings) {
  const double upper = level.lambdaMax, lower = upper / settings.smootherRatio;
  const double theta = (upper + lower) / 2, delta = (upper - lower) / 2;
  const double sigma = theta / delta;
  double rho = 1 / sigma;
  std::vector<membrane_detail::ChebyshevStep> steps{{0.0f, float(1 / theta)}};
  for (int step = 1; step < settings.smootherDegree; ++step) {
    const double rhoNext = 1 / (2 * sigma - rho);
    steps.push_back({float(rhoNext * rho), float(2 * rhoNext / delta)});
    rho = rhoNext;
  }
  return steps;
}

// One cycle of the Galerkin multigrid as a symmetric preconditioner: the post-smoother is the
// adjoint of the pre-smoother (the same Chebyshev polynomial; the band sweeps in reverse order)
// and every coarse correction is symmetric, so CG may use it.
//
// Each level's coarse problem gets `coarseCycles` cycles (2: a W-cycle). With the B-spline
// prolongation a V-cycle already keeps CG's iteration count flat from 64^2 to 256^2; the W-cycle
// saves two or three iterations and costs twice as much per iteration.
//
// The smoother and the residual of a level with device kernels (see deviceKernels) run on the
// Vulkan device; the rest of the cycle runs here.
class Preconditioner {
 public:
  Preconditioner(const MembraneHierarchy& hierarchy, const MembraneMultigridSettings& settings,
                 std::vector<membrane_detail::VulkanLevelKernels*> device)
      : hierarchy_(hierarchy), settings_(settings), device_(std::move(device)) {
    for (const Level& level : hierarchy.levels()) {
      vectors_.emplace_back(level.grid.size(), settings.coarseCycles > 1);
      steps_.push_back(chebyshevSteps(level, settings));
    }
    device_.resize(hierarchy.levels().size(), nullptr);
  }

  // z = M r on the finest level.
  void apply(const double* r, double* z) {
    const Level& finest = hierarchy_.levels().front();
    CycleVectors& v = vectors_.front();
    copyActive(finest, r, v.b.data());
    cycle(0, v.b.data(), v.x.data());
    copyActive(finest, v.x.data(), z);
  }

  // x = a first approximation of A^-1 b by nested iteration (full multigrid): b restricted to
  // every level and solved on the coarsest; on each finer level the coarser solution prolonged and
  // corrected by one cycle. A Galerkin coarse solution, prolonged, is the best approximation of the
  // finer one from the coarse space in the energy norm, so each level starts close to its own
  // solution rather than at zero. The finest level gets level 1's solution prolonged without a
  // cycle of its own: CG's first step is that cycle, with an optimal step length (on the test
  // regions it needed as many iterations or fewer than with the cycle here, at one cycle less).
  void nestedStart(const double* b, double* x) {
    const auto& levels = hierarchy_.levels();
    if (nested_.empty())
      for (const Level& level : levels)
        nested_.emplace_back(level.grid.size(), !nested_.empty());
    copyActive(levels.front(), b, nested_.front().b.data());
    for (std::size_t l = 0; l + 1 < levels.size(); ++l)
      membrane_detail::restrictToCoarse(levels[l], levels[l + 1], nested_[l].b.data(),
                                        nested_[l + 1].b.data());
    membrane_detail::solveCoarsest(hierarchy_.coarsest(), nested_.back().b.data(),
                                   nested_.back().x.data(), coarseScratch_);
    for (std::size_t l = levels.size() - 1; l-- > 0;) {
      const Level& level = levels[l];
      NestedVectors& n = nested_[l];
      std::fill(n.x.begin(), n.x.end(), 0.0f);
      membrane_detail::prolongAdd(levels[l + 1], level, nested_[l + 1].x.data(), n.x.data());
      if (l == 0) break;
      residual(l, n.b.data(), n.x.data(), n.r.data());
      cycle(l, n.r.data(), n.e.data());
      for (const membrane_detail::RowSpan& span : level.spans)
        for (int i = span.begin; i < span.end; ++i)
          n.x[std::size_t(i)] += n.e[std::size_t(i)];
    }
    copyActive(levels.front(), nested_.front().x.data(), x);
  }

 private:
  // x = (approximately) A^-1 b on level `index`.
  void cycle(std::size_t index, const float* b, float* x) {
    const auto& levels = hierarchy_.levels();
    const Level& level = levels[index];
    if (index + 1 == levels.size()) {
      membrane_detail::solveCoarsest(hierarchy_.coarsest(), b, x, coarseScratch_);
      return;
    }
    CycleVectors& v = vectors_[index];
    smooth(index, b, x, true);
    sweepBand(level, b, x, true);
    residual(index, b, x, v.r.data());
    const Level& coarse = levels[index + 1];
    CycleVectors& next = vectors_[index + 1];
    membrane_detail::restrictToCoarse(level, coarse, v.r.data(), next.b.data());
    cycle(index + 1, next.b.data(), next.x.data());
    const bool coarseIsExact = index + 2 == levels.size();
    for (int repeat = 1; repeat < settings_.coarseCycles && !coarseIsExact; ++repeat) {
      residual(index + 1, next.b.data(), next.x.data(), next.c.data());
      cycle(index + 1, next.c.data(), next.e.data());
      for (const membrane_detail::RowSpan& span : coarse.spans)
        for (int i = span.begin; i < span.end; ++i)
          next.x[std::size_t(i)] += next.e[std::size_t(i)];
    }
    membrane_detail::prolongAdd(coarse, level, next.x.data(), x);
    sweepBand(level, b, x, false);
    smooth(index, b, x, false);
  }

  void residual(std::size_t index, const float* b, const float* x, float* out) {
    if (device_[index])
      device_[index]->subtract(b, x, out);
    else
      membrane_detail::subtractOperator(hierarchy_.levels()[index], b, x, out);
  }

  // Runs the level's Chebyshev steps on x; zeroStart: x is taken as zero and overwritten.
  void smooth(std::size_t index, const float* b, float* x, bool zeroStart) {
    const Level& level = hierarchy_.levels()[index];
    std::span<const membrane_detail::ChebyshevStep> steps = steps_[index];
    float* d = vectors_[index].d.data();
    if (zeroStart) {
      // The first step from zero needs no stencil: d = gain D^-1 b, x = d.
      const float* inverseDiagonal = level.single.inverseDiagonal.data();
      const float gain = steps.front().gain;
      for (const membrane_detail::RowSpan& span : level.spans)
        for (int i = span.begin; i < span.end; ++i) {
          d[i] = gain * inverseDiagonal[i] * b[i];
          x[i] = d[i];
        }
      steps = steps.subspan(1);
    }
    if (steps.empty()) return;
    if (device_[index])
      device_[index]->chebyshev(b, x, d, steps);
    else
      smoothOnCpu(level, b, x, vectors_[index], steps);
  }

  // The iterates alternate between x and v.t; the last is copied to x when it lands in v.t.
  static void smoothOnCpu(const Level& level, const float* b, float* x, CycleVectors& v,
                          std::span<const membrane_detail::ChebyshevStep> steps) {
    float* current = x;
    float* other = v.t.data();
    for (const membrane_detail::ChebyshevStep& step : steps) {
      membrane_detail::chebyshevStep(level, b, current, other, v.d.data(), step.keep, step.gain);
      std::swap(current, other);
    }
    if (current != x) copyActive(level, current, x);
  }

  void sweepBand(const Level& level, const float* b, float* x, bool forward) {
    membrane_detail::sweepBand(level, b, x, forward, settings_.bandSweeps);
  }

  const MembraneHierarchy& hierarchy_;
  MembraneMultigridSettings settings_;
  std::vector<membrane_detail::VulkanLevelKernels*> device_;  // per level; null: on the CPU
  std::vector<CycleVectors> vectors_;
  // Per level, nestedStart's right-hand side, solution, and (but on the finest level, which gets
  // no cycle there) residual and correction.
  struct NestedVectors {
    NestedVectors(std::size_t size, bool corrected)
        : b(size, 0.0f), x(size, 0.0f), r(corrected ? size : 0, 0.0f), e(r.size(), 0.0f) {}
    std::vector<float> b, x, r, e;
  };
  std::vector<NestedVectors> nested_;  // made on nestedStart's first call
  std::vector<std::vector<membrane_detail::ChebyshevStep>> steps_;  // per level
  Eigen::VectorXd coarseScratch_;
};

// Per level, its Vulkan kernels where the options run it on the device, else null: the finest
// level and the coarse ones with at least vulkanMinUnknowns unknowns, never the coarsest (solved
// densely). Empty for the CPU kernel.
std::vector<membrane_detail::VulkanLevelKernels*> deviceKernels(const MembraneHierarchy& hierarchy,
                                                                const MembraneOptions& options) {
  std::vector<membrane_detail::VulkanLevelKernels*> device;
  if (options.kernel != MembraneKernel::Vulkan) return device;
  const auto& levels = hierarchy.levels();
  membrane_detail::VulkanCycleKernels& kernels = hierarchy.vulkanKernels();
  device.assign(levels.size(), nullptr);
  for (std::size_t l = 0; l + 1 < levels.size(); ++l)
    if (l == 0 || levels[l].unknowns.size() >= std::size_t(options.vulkanMinUnknowns))
      device[l] = &kernels.level(l);
  return device;
}

struct KrylovVectors {
  explicit KrylovVectors(std::size_t size)
      : r(size, 0.0), z(size, 0.0), p(size, 0.0), q(size, 0.0) {}
  std::vector<double> r, z, p, q;
};

// Preconditioned conjugate gradients on A x = b from the x given, stopped on the energy norm of
// the error: with M the preconditioner, r.Mr approximates ||x* - x||_A^2 (exactly for M = A^-1),
// and b.x approaches ||x*||_A^2, so CG stops at the first iterate with r.Mr <= tolerance^2 b.x.
// Unlike ||r|| / ||b||, this does not depend on where CG starts: b is large on the band of
// unknowns next to the fixed nodes, and a smooth error (what a warm or nested start leaves) has a
// residual small against it long before the error is. The test needs the z = M r of the next step
// anyway, so that step is taken too (CG's error only shrinks in the energy norm). The recurrence
// residual is then checked against the true residual b - A x; CG restarts from the true one where
// they have drifted apart, so `converged` always describes the returned x.
MembraneChannelReport conjugateGradients(const Level& finest, Preconditioner& preconditioner,
                                         const double* b, double* x, KrylovVectors& v,
                                         double tolerance, int maxIterations) {
  MembraneChannelReport report;
  const int begin = finest.activeBegin, end = finest.activeEnd;
  const double bNorm = norm(finest, b);
  if (bNorm == 0) {
    // Zero boundary data: the solution is zero.
    std::fill(x + begin, x + end, 0.0);
    report.converged = true;
    return report;
  }
  double* r = v.r.data();
  double* z = v.z.data();
  double* p = v.p.data();
  double* q = v.q.data();
  membrane_detail::subtractOperator(finest, b, x, r);
  bool restart = true;
  double rz = 0;
  while (report.iterations < maxIterations) {
    preconditioner.apply(r, z);
    const double rzNext = dot(finest, r, z);
    if (!std::isfinite(rzNext)) break;
    const bool met = rzNext <= tolerance * tolerance * dot(finest, b, x);
    if (rzNext == 0) {
      report.converged = met;  // r = 0: x solves the system
      break;
    }
    if (restart) {
      copyActive(finest, z, p);
      restart = false;
    } else {
      const double beta = rzNext / rz;
      for (const membrane_detail::RowSpan& span : finest.spans)
        for (int i = span.begin; i < span.end; ++i)
          p[i] = z[i] + beta * p[i];
    }
    rz = rzNext;
    const double pq = membrane_detail::applyOperatorDot(finest, p, q);
    if (!(pq > 0) || !(rz > 0)) {
      report.converged = met;  // breakdown: x is the iterate the test was made on
      break;
    }
    const double alpha = rz / pq;
    const double rr = membrane_detail::updateResidual(finest, alpha, p, q, x, r);
    ++report.iterations;
    if (!met) continue;
    membrane_detail::subtractOperator(finest, b, x, q);
    double drift = 0;
    for (const membrane_detail::RowSpan& span : finest.spans)
      for (int i = span.begin; i < span.end; ++i)
        drift += (q[i] - r[i]) * (q[i] - r[i]);
    if (drift <= 0.25 * rr) {
      report.converged = true;
      break;
    }
    copyActive(finest, q, r);
    restart = true;
  }
  membrane_detail::subtractOperator(finest, b, x, r);
  report.residual = norm(finest, r) / bNorm;
  return report;
}

// Solves the channels c = first, first + step, ... on the calling thread. Each channel's
// arithmetic is the same whichever thread runs it, so the values do not depend on the thread
// count. (Splitting rows between threads instead would need a barrier after every kernel, about
// a hundred per V-cycle, most of them on coarse levels too small to share.)
void solveChannels(const MembraneProblem& problem, const MembraneOptions& options,
                   const std::vector<std::vector<double>>& initialGuess,
                   const MembraneHierarchy& hierarchy, const std::vector<int>& fixedNodes,
                   const std::vector<int>& unknownNodes, std::size_t first, std::size_t step,
                   MembraneResult& result) {
  const Level& finest = hierarchy.levels().front();
  Preconditioner preconditioner(hierarchy, options.multigrid, deviceKernels(hierarchy, options));
  KrylovVectors krylov(finest.grid.size());
  for (std::size_t c = first; c < problem.channels.size(); c += step) {
    const std::vector<double>& field = problem.channels[c];
    const std::vector<double> b = membrane_detail::rightHandSide(
        finest, membrane_detail::padded(finest.grid, field, fixedNodes));
    std::vector<double> x(finest.grid.size(), 0.0);
    if (initialGuess.empty())
      preconditioner.nestedStart(b.data(), x.data());
    else
      x = membrane_detail::padded(finest.grid, initialGuess[c], unknownNodes);
    result.channels[c] = conjugateGradients(finest, preconditioner, b.data(), x.data(), krylov,
                                            options.tolerance, options.maxIterations);
    std::vector<double>& values = result.values[c];
    values = field;
    for (int i : unknownNodes)
      values[std::size_t(i)] =
          x[std::size_t(finest.grid.index(i % problem.width, i / problem.width))];
  }
}

std::size_t workerCount(int requested) {
  if (requested > 0) return std::size_t(requested);
  return std::max(1u, std::thread::hardware_concurrency());
}

// The settings, and the initial guess's size (its values are checked with the roles).
void validateOptions(const MembraneOptions& options, const MembraneProblem& problem) {
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw std::invalid_argument("membrane: the tolerance must be positive and finite");
  if (options.maxIterations < 0)
    throw std::invalid_argument("membrane: maxIterations must not be negative");
  if (options.threads < 0) throw std::invalid_argument("membrane: threads must not be negative");
  if (options.vulkanMinUnknowns < 0)
    throw std::invalid_argument("membrane: vulkanMinUnknowns must not be negative");
  const MembraneMultigridSettings& m = options.multigrid;
  if (m.smootherDegree < 1 || !(m.smootherRatio > 1) || !std::isfinite(m.smootherRatio) ||
      m.bandWidth < 0 || m.bandSweeps < 0 || m.coarseCycles < 1 || m.coarsestUnknowns < 1)
    throw std::invalid_argument(
        "membrane: multigrid settings need smootherDegree >= 1, a finite smootherRatio > 1, "
        "bandWidth >= 0, bandSweeps >= 0, coarseCycles >= 1 and coarsestUnknowns >= 1");
  if (options.initialGuess.empty()) return;
  membrane_detail::validateFields(options.initialGuess, problem.channels.size(),
                                  problem.inside.size(), "the initial guess");
}

}  // namespace

std::vector<MembraneNode> classifyMembraneNodes(int width, int height,
                                                const std::vector<std::uint8_t>& inside,
                                                MembraneContinuity continuity) {
  membrane_detail::validateRegion(width, height, inside);
  const int reach = continuity == MembraneContinuity::C1 ? 2 : 1;
  std::vector<MembraneNode> roles(inside.size(), MembraneNode::Unused);
  auto at = [width](int x, int y) { return std::size_t(y) * std::size_t(width) + std::size_t(x); };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!inside[at(x, y)]) continue;
      roles[at(x, y)] = MembraneNode::Unknown;
      // The nodes the stencil reads: taxicab distance up to `reach`.
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach + std::abs(dy); dx <= reach - std::abs(dy); ++dx)
          if (!inside[at(x + dx, y + dy)]) roles[at(x + dx, y + dy)] = MembraneNode::Fixed;
    }
  return roles;
}

namespace {

// The part of the grid a solve runs on: Q's bounding box grown by the fixed rings and by a margin,
// rounded out to multiples of kWindowQuantum nodes (within the grid); or the previous hierarchy's
// window while it holds them, so that the window, and with it the hierarchy that the next dab
// updates, stays the same while a stroke grows inside it. A brush's Q covers a few percent of its
// grid: every pass of the solve and of the hierarchy's setup then follows Q's size, not the
// grid's. The discrete problem on the window is the same (all of Q and its fixed rings lie in it);
// the coarse levels lie on the window, so the preconditioner, and the iterates within the
// tolerance, differ with it.
constexpr int kWindowQuantum = 16;
constexpr int kWindowMargin = 16;

using membrane_detail::GridWindow;

GridWindow solveWindow(const MembraneProblem& problem, const MembraneHierarchy* previous) {
  int minX = problem.width, minY = problem.height, maxX = -1, maxY = -1;
  for (int y = 0; y < problem.height; ++y) {
    const std::uint8_t* row = problem.inside.data() + std::size_t(y) * std::size_t(problem.width);
    int first = 0, last = problem.width - 1;
    while (first < problem.width && !row[first])
      ++first;
    if (first == problem.width) continue;
    while (!row[last])
      --last;
    minX = std::min(minX, first);
    maxX = std::max(maxX, last);
    minY = std::min(minY, y);
    maxY = y;
  }
  constexpr int rings = membrane_detail::kRings;
  const GridWindow needed{minX - rings, minY - rings, maxX - minX + 1 + 2 * rings,
                          maxY - minY + 1 + 2 * rings};
  if (previous && previous->problemWidth() == problem.width &&
      previous->problemHeight() == problem.height && previous->window().contains(needed))
    return previous->window();
  auto down = [](int v) { return std::max(0, v / kWindowQuantum * kWindowQuantum); };
  auto up = [](int v, int size) {
    return std::min(size, (v + kWindowQuantum - 1) / kWindowQuantum * kWindowQuantum);
  };
  GridWindow window;
  window.x = down(needed.x - kWindowMargin);
  window.y = down(needed.y - kWindowMargin);
  window.width = up(needed.x + needed.width + kWindowMargin, problem.width) - window.x;
  window.height = up(needed.y + needed.height + kWindowMargin, problem.height) - window.y;
  return window;
}

template <typename T>
std::vector<T> cropField(const std::vector<T>& field, int fieldWidth, const GridWindow& window) {
  std::vector<T> out(std::size_t(window.width) * std::size_t(window.height));
  for (int y = 0; y < window.height; ++y) {
    const auto from = field.begin() + std::ptrdiff_t(y + window.y) * fieldWidth + window.x;
    std::copy(from, from + window.width, out.begin() + std::ptrdiff_t(y) * window.width);
  }
  return out;
}

std::vector<std::vector<double>> cropFields(const std::vector<std::vector<double>>& fields,
                                            int fieldWidth, const GridWindow& window) {
  std::vector<std::vector<double>> out;
  out.reserve(fields.size());
  for (const std::vector<double>& field : fields)
    out.push_back(cropField(field, fieldWidth, window));
  return out;
}

// The solve of a validated problem whose grid is the window.
MembraneResult solveOnWindow(const MembraneProblem& problem, const std::vector<MembraneNode>& roles,
                             const MembraneOptions& options,
                             const std::vector<std::vector<double>>& initialGuess,
                             const GridWindow& window, int problemWidth, int problemHeight) {
  MembraneResult result;
  result.hierarchyReused = options.hierarchy && options.hierarchy->fits(problem, options.multigrid);
  if (result.hierarchyReused) {
    result.hierarchy = options.hierarchy;
  } else {
    auto hierarchy = std::make_shared<MembraneHierarchy>(
        problem.width, problem.height, problem.inside, problem.continuity, options.multigrid,
        options.hierarchy.get(), options.threads);
    hierarchy->placeOn(window, problemWidth, problemHeight);
    result.hierarchy = std::move(hierarchy);
  }
  const auto& levels = result.hierarchy->levels();
  const Level& finest = levels.front();
  result.levels = int(levels.size());
  result.unknowns = int(finest.unknowns.size());
  result.kernel = options.kernel;
  // Made here, before the workers start, so that a missing device throws on this thread.
  for (const auto* device : deviceKernels(*result.hierarchy, options))
    result.vulkanLevels += device != nullptr;

  const std::vector<int> fixedNodes = membrane_detail::nodesOf(roles, MembraneNode::Fixed);
  const std::vector<int> unknownNodes = membrane_detail::nodesOf(roles, MembraneNode::Unknown);
  const std::size_t channels = problem.channels.size();
  result.channels.resize(channels);
  result.values.resize(channels);
  const std::size_t threads = std::min(channels, workerCount(options.threads));
  std::vector<std::thread> workers;
  std::vector<std::exception_ptr> failures(threads);
  auto solve = [&](std::size_t first) {
    try {
      solveChannels(problem, options, initialGuess, *result.hierarchy, fixedNodes, unknownNodes,
                    first, threads, result);
    } catch (...) {
      failures[first] = std::current_exception();
    }
  };
  for (std::size_t t = 1; t < threads; ++t)
    workers.emplace_back(solve, t);
  solve(0);
  for (std::thread& worker : workers)
    worker.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);

  result.converged = true;
  for (const MembraneChannelReport& report : result.channels) {
    result.iterations = std::max(result.iterations, report.iterations);
    result.residual = std::max(result.residual, report.residual);
    result.converged = result.converged && report.converged;
  }
  return result;
}

}  // namespace

MembraneResult solveMembrane(const MembraneProblem& problem, const MembraneOptions& options) {
  // Checked on the whole grid where it is cheap (the region, the sizes, the settings), on the
  // window where it follows the nodes' roles; a failure there is checked again on the whole grid,
  // whose message names the node in the caller's numbering.
  membrane_detail::validateRegion(problem.width, problem.height, problem.inside);
  if (problem.channels.empty())
    throw std::invalid_argument("membrane: the problem has no channels");
  membrane_detail::validateFields(problem.channels, problem.channels.size(), problem.inside.size(),
                                  "the boundary data");
  validateOptions(options, problem);
  const GridWindow window = solveWindow(problem, options.hierarchy.get());
  const bool whole = window.width == problem.width && window.height == problem.height;
  MembraneProblem cropped;
  if (!whole) {
    cropped.width = window.width;
    cropped.height = window.height;
    cropped.inside = cropField(problem.inside, problem.width, window);
    cropped.channels = cropFields(problem.channels, problem.width, window);
    cropped.continuity = problem.continuity;
  }
  const MembraneProblem& local = whole ? problem : cropped;
  const std::vector<std::vector<double>> croppedGuess =
      whole ? std::vector<std::vector<double>>()
            : cropFields(options.initialGuess, problem.width, window);
  const std::vector<std::vector<double>>& initialGuess =
      whole ? options.initialGuess : croppedGuess;
  const std::vector<MembraneNode> roles =
      classifyMembraneNodes(local.width, local.height, local.inside, local.continuity);
  if (!membrane_detail::allFinite(local.channels, roles, MembraneNode::Fixed) ||
      !membrane_detail::allFinite(initialGuess, roles, MembraneNode::Unknown)) {
    const std::vector<MembraneNode> allRoles = membrane_detail::validateProblem(problem);
    membrane_detail::requireFinite(options.initialGuess, allRoles, MembraneNode::Unknown,
                                   "the initial guess");
  }

  MembraneResult result =
      solveOnWindow(local, roles, options, initialGuess, window, problem.width, problem.height);
  if (whole) return result;
  // Back on the whole grid: the problem's values, the window's solved unknowns over them.
  for (std::size_t c = 0; c < result.values.size(); ++c) {
    std::vector<double> values = problem.channels[c];
    const std::vector<double>& solved = result.values[c];
    for (int y = 0; y < window.height; ++y) {
      const auto from = solved.begin() + std::ptrdiff_t(y) * window.width;
      std::copy(from, from + window.width,
                values.begin() + std::ptrdiff_t(y + window.y) * problem.width + window.x);
    }
    result.values[c] = std::move(values);
  }
  return result;
}

std::vector<double> membraneResidual(const MembraneProblem& problem,
                                     const std::vector<std::vector<double>>& values) {
  const std::vector<MembraneNode> roles = membrane_detail::validateProblem(problem);
  membrane_detail::validateFields(values, problem.channels.size(), problem.inside.size(),
                                  "the values");
  membrane_detail::requireFinite(values, roles, MembraneNode::Unknown, "the value");
  const Level finest = membrane_detail::finestLevel(problem.width, problem.height, problem.inside,
                                                    problem.continuity, 0);
  std::vector<double> residuals;
  std::vector<double> r(finest.grid.size(), 0.0);
  for (std::size_t c = 0; c < problem.channels.size(); ++c) {
    const std::vector<double> b = membrane_detail::rightHandSide(
        finest,
        membrane_detail::padded(finest.grid, problem.channels[c], roles, MembraneNode::Fixed));
    const std::vector<double> x =
        membrane_detail::padded(finest.grid, values[c], roles, MembraneNode::Unknown);
    membrane_detail::subtractOperator(finest, b.data(), x.data(), r.data());
    const double bNorm = norm(finest, b.data()), rNorm = norm(finest, r.data());
    residuals.push_back(bNorm > 0 ? rNorm / bNorm : rNorm);
  }
  return residuals;
}

}  // namespace geobrush
