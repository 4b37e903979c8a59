#include "membrane.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/gpu/vulkan_context.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/stitch.hpp"
#include "geobrush/values.hpp"
#include "membrane_boundary.hpp"
#include "membrane_levels.hpp"
#include "membrane_vulkan.hpp"
#include "roi.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

using Mask = std::vector<std::uint8_t>;
using Field = std::vector<double>;
using Function = std::function<double(double u, double v)>;

// Region shapes on an n x n grid, all at least two nodes from the border.
Mask maskFrom(int n, const std::function<bool(double dx, double dy)>& inside) {
  Mask mask(std::size_t(n) * std::size_t(n), 0);
  const double center = (n - 1) / 2.0;
  for (int y = 2; y < n - 2; ++y)
    for (int x = 2; x < n - 2; ++x)
      mask[std::size_t(y) * std::size_t(n) + std::size_t(x)] = inside(x - center, y - center);
  return mask;
}

Mask disc(int n) {
  const double radius = n / 2.0 - 4;
  return maskFrom(n, [=](double dx, double dy) { return std::hypot(dx, dy) < radius; });
}

Mask square(int n) {
  const double half = n / 2.0 - 4;
  return maskFrom(n,
                  [=](double dx, double dy) { return std::abs(dx) < half && std::abs(dy) < half; });
}

// Two boundary loops: the outer one with a notch that does not cut through the ring.
Mask annulusWithNotch(int n) {
  const double outer = n / 2.0 - 4, inner = 0.4 * outer;
  return maskFrom(n, [=](double dx, double dy) {
    const double r = std::hypot(dx, dy);
    const bool notch = dx > 0 && std::abs(dy) < n / 16.0 && r > 0.7 * outer;
    return r < outer && r > inner && !notch;
  });
}

// Disc with a notch, as the benchmark uses.
Mask notchedDisc(int n) {
  const double radius = n / 2.0 - 4;
  return maskFrom(n, [=](double dx, double dy) {
    return std::hypot(dx, dy) < radius && !(dx > 0 && std::abs(dy) < n / 20.0);
  });
}

// Two components: two boundary loops, and a coarse level where they nearly touch.
Mask twoDiscs(int n) {
  return maskFrom(n, [=](double dx, double dy) {
    return std::hypot(dx + n / 5.0, dy) < n / 5.0 || std::hypot(dx - n / 4.0, dy) < n / 6.0;
  });
}

// Two discs joined by a channel two nodes wide.
Mask channel(int n) {
  return maskFrom(n, [=](double dx, double dy) {
    const bool link = dx >= 0.5 && dx < 2.5 && std::abs(dy) < n / 4.0;
    return link || std::hypot(dx, dy - n / 4.0) < n / 8.0 || std::hypot(dx, dy + n / 4.0) < n / 8.0;
  });
}

struct Shape {
  const char* name;
  Mask (*make)(int);
};

void PrintTo(const Shape& shape, std::ostream* out) {
  *out << shape.name;
}

const Shape kShapes[] = {{"disc", disc},
                         {"square", square},
                         {"annulus_with_notch", annulusWithNotch},
                         {"notched_disc", notchedDisc},
                         {"two_discs", twoDiscs},
                         {"channel", channel}};

// Node (x, y) sits at (u, v) = (x, y) / n.
Field sample(int n, const Function& f) {
  Field field(std::size_t(n) * std::size_t(n));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      field[std::size_t(y) * std::size_t(n) + std::size_t(x)] = f(double(x) / n, double(y) / n);
  return field;
}

// Boundary data that is not biharmonic: the solution differs from it inside Q.
Function smoothData(int channel) {
  return [channel](double u, double v) {
    return std::sin(3 * u + channel) * std::cos(2 * v) + (channel + 1) * u * u - v;
  };
}

MembraneProblem problemOn(int n, Mask mask, int channels = 3,
                          MembraneContinuity continuity = MembraneContinuity::C1) {
  MembraneProblem problem;
  problem.width = problem.height = n;
  problem.inside = std::move(mask);
  problem.continuity = continuity;
  for (int c = 0; c < channels; ++c)
    problem.channels.push_back(sample(n, smoothData(c)));
  return problem;
}

// max |a - b| over Q, relative to max |b| over Q.
double relativeError(const MembraneProblem& problem, const Field& a, const Field& b) {
  double error = 0, scale = 0;
  for (std::size_t i = 0; i < problem.inside.size(); ++i)
    if (problem.inside[i]) {
      error = std::max(error, std::abs(a[i] - b[i]));
      scale = std::max(scale, std::abs(b[i]));
    }
  return error / scale;
}

double maxErrorInside(const MembraneProblem& problem, const Field& values, const Function& f) {
  const int n = problem.width;
  double error = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (problem.inside[std::size_t(y) * std::size_t(n) + std::size_t(x)])
        error = std::max(error, std::abs(values[std::size_t(y) * std::size_t(n) + std::size_t(x)] -
                                         f(double(x) / n, double(y) / n)));
  return error;
}

// (a) The multigrid-preconditioned CG agrees with the sparse direct solve of the same system.
class MembraneShapes : public ::testing::TestWithParam<std::tuple<Shape, int>> {};

TEST_P(MembraneShapes, MatchesDirectSolve) {
  const auto [shape, n] = GetParam();
  const MembraneProblem problem = problemOn(n, shape.make(n));
  const MembraneResult iterative = solveMembrane(problem);
  const MembraneDirectResult direct = solveMembraneDirect(problem);
  ASSERT_TRUE(iterative.converged);
  EXPECT_LE(iterative.residual, 1e-6);
  EXPECT_LE(direct.residual, 1e-12);
  for (std::size_t c = 0; c < problem.channels.size(); ++c)
    EXPECT_LE(relativeError(problem, iterative.values[c], direct.values[c]), 1e-4)
        << shape.name << " " << n << " channel " << c;
}

// (c) The iteration count does not grow with the grid or depend much on the shape.
TEST_P(MembraneShapes, IterationsStayBounded) {
  const auto [shape, n] = GetParam();
  const MembraneResult result = solveMembrane(problemOn(n, shape.make(n)));
  ASSERT_TRUE(result.converged);
  EXPECT_LE(result.iterations, 12) << shape.name << " " << n;
  EXPECT_GE(result.levels, 3) << "the test must exercise the coarse levels";
}

INSTANTIATE_TEST_SUITE_P(Shapes, MembraneShapes,
                         ::testing::Combine(::testing::ValuesIn(kShapes),
                                            ::testing::Values(64, 128)),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param).name) + "_" +
                                  std::to_string(std::get<1>(info.param));
                         });

TEST(Membrane, IterationsStayBoundedAt256) {
  for (const Shape& shape : kShapes) {
    const MembraneResult result = solveMembrane(problemOn(256, shape.make(256), 1));
    ASSERT_TRUE(result.converged) << shape.name;
    EXPECT_LE(result.iterations, 12) << shape.name;
  }
}

TEST(Membrane, HarmonicModeMatchesDirectSolve) {
  for (const Shape& shape : kShapes) {
    const MembraneProblem problem = problemOn(64, shape.make(64), 2, MembraneContinuity::C0);
    const MembraneResult iterative = solveMembrane(problem);
    const MembraneDirectResult direct = solveMembraneDirect(problem);
    ASSERT_TRUE(iterative.converged) << shape.name;
    EXPECT_LE(iterative.iterations, 12) << shape.name;
    for (std::size_t c = 0; c < problem.channels.size(); ++c)
      EXPECT_LE(relativeError(problem, iterative.values[c], direct.values[c]), 1e-4) << shape.name;
  }
}

TEST(Membrane, WCycleAgreesWithFewerIterations) {
  const MembraneProblem problem = problemOn(96, notchedDisc(96), 1);
  MembraneOptions w;
  w.multigrid.coarseCycles = 2;
  const MembraneResult vResult = solveMembrane(problem);
  const MembraneResult wResult = solveMembrane(problem, w);
  ASSERT_TRUE(wResult.converged);
  EXPECT_LT(wResult.iterations, vResult.iterations);
  EXPECT_LE(relativeError(problem, wResult.values[0], solveMembraneDirect(problem).values[0]),
            1e-4);
}

// (b) The 13-point stencil is exact for cubics, and every cubic is biharmonic: with both fixed
// rings sampled from one, the discrete solution is that cubic.
TEST(Membrane, ReproducesCubicFromItsBoundaryData) {
  const Function cubic = [](double u, double v) {
    return u * u * u - 3 * u * v * v + u * u * v + 0.5 * v * v * v - 2 * u * v + u - 0.3 * v + 1;
  };
  for (const Shape& shape : {kShapes[2], kShapes[5]}) {
    MembraneProblem problem = problemOn(96, shape.make(96), 0);
    problem.channels = {sample(96, cubic)};
    MembraneOptions options;
    options.tolerance = 1e-12;
    const MembraneResult result = solveMembrane(problem, options);
    ASSERT_TRUE(result.converged) << shape.name;
    EXPECT_LE(maxErrorInside(problem, result.values[0], cubic), 1e-9) << shape.name;
    EXPECT_LE(maxErrorInside(problem, solveMembraneDirect(problem).values[0], cubic), 1e-10)
        << shape.name;
  }
}

// The 5-point Laplacian is exact for these harmonic polynomials: one fixed ring reproduces them.
TEST(Membrane, HarmonicModeReproducesHarmonicPolynomials) {
  const Function harmonic[] = {[](double u, double v) { return u * u - v * v; },
                               [](double u, double v) { return u * u * u - 3 * u * v * v + v; }};
  for (const Function& f : harmonic) {
    MembraneProblem problem = problemOn(80, annulusWithNotch(80), 0, MembraneContinuity::C0);
    problem.channels = {sample(80, f)};
    MembraneOptions options;
    options.tolerance = 1e-12;
    const MembraneResult result = solveMembrane(problem, options);
    ASSERT_TRUE(result.converged);
    EXPECT_LE(maxErrorInside(problem, result.values[0], f), 1e-9);
  }
}

// The derivative constraints are what carry the slope: a cubic that is not harmonic is reproduced
// with them (C1) and not without them (C0).
TEST(Membrane, DerivativeConstraintsCarryTheSlope) {
  const Function f = [](double u, double v) { return u * u * u + 2 * u * v * v - v * v; };
  MembraneProblem plate = problemOn(64, disc(64), 0);
  plate.channels = {sample(64, f)};
  MembraneProblem membrane = plate;
  membrane.continuity = MembraneContinuity::C0;
  MembraneOptions options;
  options.tolerance = 1e-12;
  EXPECT_LE(maxErrorInside(plate, solveMembrane(plate, options).values[0], f), 1e-9);
  EXPECT_GE(maxErrorInside(membrane, solveMembrane(membrane, options).values[0], f), 1e-3);
}

TEST(Membrane, ClassifiesTwoFixedRingsForC1AndOneForC0) {
  Mask single(49, 0);
  single[3 * 7 + 3] = 1;
  const auto plate = classifyMembraneNodes(7, 7, single, MembraneContinuity::C1);
  const auto membrane = classifyMembraneNodes(7, 7, single, MembraneContinuity::C0);
  auto count = [](const std::vector<MembraneNode>& roles, MembraneNode role) {
    return std::count(roles.begin(), roles.end(), role);
  };
  EXPECT_EQ(count(plate, MembraneNode::Unknown), 1);
  EXPECT_EQ(count(plate, MembraneNode::Fixed), 12);  // taxicab distance 1 and 2
  EXPECT_EQ(plate[3 * 7 + 5], MembraneNode::Fixed);
  EXPECT_EQ(plate[4 * 7 + 4], MembraneNode::Fixed);
  EXPECT_EQ(plate[5 * 7 + 4], MembraneNode::Unused);
  EXPECT_EQ(count(membrane, MembraneNode::Fixed), 4);
  EXPECT_EQ(membrane[4 * 7 + 4], MembraneNode::Unused);
}

// Values the solver does not read may be anything, NaN included.
TEST(Membrane, IgnoresValuesAtUnusedAndUnknownNodes) {
  MembraneProblem problem = problemOn(48, disc(48), 1);
  const MembraneResult clean = solveMembrane(problem);
  const auto roles = classifyMembraneNodes(48, 48, problem.inside, MembraneContinuity::C1);
  for (std::size_t i = 0; i < roles.size(); ++i)
    if (roles[i] != MembraneNode::Fixed)
      problem.channels[0][i] = std::numeric_limits<double>::quiet_NaN();
  const MembraneResult dirty = solveMembrane(problem);
  ASSERT_TRUE(dirty.converged);
  for (std::size_t i = 0; i < roles.size(); ++i)
    if (roles[i] == MembraneNode::Unknown) {
      ASSERT_EQ(dirty.values[0][i], clean.values[0][i]);
    }
}

// (d) After a dab grows Q, the previous solution is a start that needs few iterations, and the
// answer is the direct solve's. So is the nested-iteration start the solver makes without one;
// a start from zero needs twice as many. The stopping test bounds the error whatever the start.
TEST(Membrane, WarmStartAfterADabNeedsFewIterations) {
  const int n = 128;
  const MembraneProblem before = problemOn(n, notchedDisc(n));
  const MembraneResult previous = solveMembrane(before);
  ASSERT_TRUE(previous.converged);

  // The dab fills the inner end of the notch, where the membrane now replaces the data.
  MembraneProblem after = before;
  const Mask dab =
      maskFrom(n, [=](double dx, double dy) { return std::hypot(dx - 0.15 * n, dy) < n / 12.0; });
  for (std::size_t i = 0; i < dab.size(); ++i)
    after.inside[i] = after.inside[i] || dab[i];
  ASSERT_NE(after.inside, before.inside);
  // The new unknowns start from the boundary data they carried before the dab.
  MembraneOptions warm;
  warm.initialGuess = previous.values;
  warm.hierarchy = previous.hierarchy;
  const MembraneResult warmResult = solveMembrane(after, warm);
  const MembraneResult nestedResult = solveMembrane(after);
  MembraneOptions zero;
  zero.initialGuess.assign(after.channels.size(), Field(after.inside.size(), 0.0));
  const MembraneResult zeroResult = solveMembrane(after, zero);
  const MembraneDirectResult direct = solveMembraneDirect(after);
  ASSERT_TRUE(warmResult.converged);
  ASSERT_TRUE(nestedResult.converged);
  ASSERT_TRUE(zeroResult.converged);
  EXPECT_FALSE(warmResult.hierarchyReused);
  // At least one: else the previous solution already passed and the test would prove nothing.
  EXPECT_GE(warmResult.iterations, 1);
  EXPECT_LE(warmResult.iterations, 3);
  EXPECT_LE(nestedResult.iterations, 3);
  EXPECT_GE(zeroResult.iterations, 6);
  const std::pair<const char*, const MembraneResult*> starts[] = {
      {"warm", &warmResult}, {"nested", &nestedResult}, {"zero", &zeroResult}};
  for (const auto& [name, result] : starts)
    for (std::size_t c = 0; c < after.channels.size(); ++c)
      EXPECT_LE(relativeError(after, result->values[c], direct.values[c]), 1e-4)
          << name << " start, channel " << c;
}

TEST(Membrane, ReusesTheHierarchyWhileQIsUnchanged) {
  const MembraneProblem first = problemOn(64, annulusWithNotch(64), 1);
  const MembraneResult firstResult = solveMembrane(first);
  EXPECT_FALSE(firstResult.hierarchyReused);

  MembraneProblem second = first;
  second.channels = {sample(64, smoothData(2))};
  MembraneOptions reuse;
  reuse.hierarchy = firstResult.hierarchy;
  const MembraneResult reused = solveMembrane(second, reuse);
  EXPECT_TRUE(reused.hierarchyReused);
  EXPECT_EQ(reused.hierarchy, firstResult.hierarchy);
  EXPECT_EQ(reused.values, solveMembrane(second).values);

  MembraneProblem harmonic = second;
  harmonic.continuity = MembraneContinuity::C0;
  EXPECT_FALSE(solveMembrane(harmonic, reuse).hierarchyReused);
  MembraneOptions otherBand = reuse;
  otherBand.multigrid.bandWidth = 2;
  EXPECT_FALSE(solveMembrane(second, otherBand).hierarchyReused);
}

// A hierarchy updated from the previous dab's copies the rows the dab did not reach: the solve is
// the same, bit for bit, as with a hierarchy built from scratch.
TEST(Membrane, UpdatedHierarchyGivesTheSameSolution) {
  const int n = 96;
  const MembraneProblem before = problemOn(n, annulusWithNotch(n), 2);
  const MembraneResult previous = solveMembrane(before);
  MembraneProblem after = before;
  // The dab covers part of the hole.
  const Mask dab =
      maskFrom(n, [=](double dx, double dy) { return std::hypot(dx - 0.1 * n, dy) < n / 10.0; });
  for (std::size_t i = 0; i < dab.size(); ++i)
    after.inside[i] = after.inside[i] || dab[i];
  ASSERT_NE(after.inside, before.inside);
  MembraneOptions update;
  update.hierarchy = previous.hierarchy;
  const MembraneResult updated = solveMembrane(after, update);
  const MembraneResult fresh = solveMembrane(after);
  EXPECT_FALSE(updated.hierarchyReused);
  EXPECT_NE(updated.hierarchy, previous.hierarchy);
  EXPECT_EQ(updated.levels, fresh.levels);
  EXPECT_EQ(updated.values, fresh.values);
}

// A disc of radius `radius` nodes around node (x, y) of an n x n grid.
Mask discAt(int n, double x, double y, double radius) {
  Mask mask(std::size_t(n) * std::size_t(n), 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      mask[std::size_t(j) * std::size_t(n) + std::size_t(i)] = std::hypot(i - x, j - y) < radius;
  return mask;
}

// A small Q on a large grid is solved on a window around it (here one Q beside the grid's border,
// where the window is cut short): the same system, so the direct solve's answer, and every node
// off Q keeps the problem's value, bit for bit.
TEST(Membrane, SolvesASmallRegionOnAWindowAroundIt) {
  const int n = 160;
  for (const auto& [x, y] : {std::pair{40.0, 100.0}, {12.0, 148.0}}) {
    const MembraneProblem problem = problemOn(n, discAt(n, x, y, 9.5));
    const MembraneResult result = solveMembrane(problem);
    ASSERT_TRUE(result.converged);
    const membrane_detail::GridWindow window = result.hierarchy->window();
    EXPECT_LT(window.width * window.height, n * n / 4) << "the solve ran on the whole grid";
    EXPECT_EQ(result.hierarchy->levels().front().grid.width, window.width);
    EXPECT_EQ(result.hierarchy->problemWidth(), n);
    const MembraneDirectResult direct = solveMembraneDirect(problem);
    for (std::size_t c = 0; c < problem.channels.size(); ++c) {
      EXPECT_LE(relativeError(problem, result.values[c], direct.values[c]), 1e-4);
      for (std::size_t i = 0; i < problem.inside.size(); ++i)
        if (!problem.inside[i]) {
          ASSERT_EQ(result.values[c][i], problem.channels[c][i]) << i;
        }
    }
  }
}

// While a stroke's dabs stay inside the previous hierarchy's window, the next solve keeps that
// window (and updates the hierarchy on it); a dab outside it moves the window.
TEST(Membrane, AStrokeKeepsItsWindowWhileItsDabsFitInIt) {
  const int n = 200;
  MembraneProblem problem = problemOn(n, discAt(n, 60, 60, 8));
  MembraneOptions options;
  options.tolerance = 1e-7;
  MembraneResult previous = solveMembrane(problem, options);
  const membrane_detail::GridWindow first = previous.hierarchy->window();
  auto addDab = [&](double x, double y) {
    const Mask dab = discAt(n, x, y, 8);
    for (std::size_t i = 0; i < dab.size(); ++i)
      problem.inside[i] = problem.inside[i] || dab[i];
    options.initialGuess = previous.values;
    options.hierarchy = previous.hierarchy;
    previous = solveMembrane(problem, options);
    ASSERT_TRUE(previous.converged);
    EXPECT_FALSE(previous.hierarchyReused);
    const MembraneDirectResult direct = solveMembraneDirect(problem);
    for (std::size_t c = 0; c < problem.channels.size(); ++c)
      EXPECT_LE(relativeError(problem, previous.values[c], direct.values[c]), 1e-4);
  };
  addDab(64, 62);
  EXPECT_EQ(previous.hierarchy->window(), first);
  addDab(140, 130);
  EXPECT_NE(previous.hierarchy->window(), first);
  EXPECT_TRUE(previous.hierarchy->window().contains(first));
}

// The coarse rows of a hierarchy are computed on several threads: the hierarchy is the same, bit
// for bit, for every thread count, built from scratch or updated from the previous region's.
TEST(Membrane, HierarchyIsTheSameForEveryThreadCount) {
  const int n = 128;  // enough unknowns for the finest coarsening to run on several threads
  const Mask before = annulusWithNotch(n);
  Mask after = before;
  const Mask dab =
      maskFrom(n, [=](double dx, double dy) { return std::hypot(dx - 0.1 * n, dy) < n / 10.0; });
  for (std::size_t i = 0; i < dab.size(); ++i)
    after[i] = after[i] || dab[i];
  const MembraneMultigridSettings settings;
  const MembraneHierarchy previous(n, n, before, MembraneContinuity::C1, settings);
  const MembraneHierarchy one(n, n, after, MembraneContinuity::C1, settings, nullptr, 1);
  ASSERT_GE(one.levels().front().unknowns.size(), 4096u);
  for (int threads : {2, 3}) {
    for (const MembraneHierarchy* from :
         {static_cast<const MembraneHierarchy*>(nullptr), &previous}) {
      const MembraneHierarchy other(n, n, after, MembraneContinuity::C1, settings, from, threads);
      ASSERT_EQ(other.levels().size(), one.levels().size());
      for (std::size_t l = 0; l < one.levels().size(); ++l) {
        const membrane_detail::Level& a = one.levels()[l];
        const membrane_detail::Level& b = other.levels()[l];
        EXPECT_EQ(a.mask, b.mask);
        EXPECT_EQ(a.lambdaMax, b.lambdaMax);
        ASSERT_EQ(a.customRows.size(), b.customRows.size());
        for (std::size_t c = 0; c < a.customRows.size(); ++c) {
          EXPECT_EQ(a.customRows[c].node, b.customRows[c].node);
          EXPECT_EQ(a.customRows[c].weights, b.customRows[c].weights);
        }
      }
    }
  }
}

// (e) Bit-identical on every run and for every thread count.
TEST(Membrane, IsDeterministicAcrossRunsAndThreadCounts) {
  const MembraneProblem problem = problemOn(96, channel(96), 3);
  MembraneOptions options;
  options.threads = 1;
  const MembraneResult one = solveMembrane(problem, options);
  const MembraneResult again = solveMembrane(problem, options);
  options.threads = 2;
  const MembraneResult two = solveMembrane(problem, options);
  options.threads = 3;
  const MembraneResult three = solveMembrane(problem, options);
  EXPECT_EQ(one.values, again.values);
  EXPECT_EQ(one.values, two.values);
  EXPECT_EQ(one.values, three.values);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(one.channels[c].iterations, two.channels[c].iterations);
    EXPECT_EQ(one.channels[c].residual, two.channels[c].residual);
  }
}

// A solve that stops early says so, and reports the residual it reached.
TEST(Membrane, ReportsNonConvergence) {
  const MembraneProblem problem = problemOn(64, notchedDisc(64), 1);
  MembraneOptions options;
  options.tolerance = 1e-13;
  options.maxIterations = 2;
  const MembraneResult result = solveMembrane(problem, options);
  EXPECT_FALSE(result.converged);
  EXPECT_FALSE(result.channels[0].converged);
  EXPECT_EQ(result.iterations, 2);
  EXPECT_GT(result.residual, 1e-13);
  EXPECT_NEAR(membraneResidual(problem, result.values)[0], result.residual,
              1e-9 * result.residual + 1e-15);

  options.maxIterations = 0;
  EXPECT_FALSE(solveMembrane(problem, options).converged);
}

TEST(Membrane, ZeroBoundaryDataGivesZero) {
  MembraneProblem problem = problemOn(32, disc(32), 1);
  std::fill(problem.channels[0].begin(), problem.channels[0].end(), 0.0);
  MembraneOptions options;
  options.initialGuess = {sample(32, smoothData(1))};
  const MembraneResult result = solveMembrane(problem, options);
  EXPECT_TRUE(result.converged);
  for (std::size_t i = 0; i < problem.inside.size(); ++i)
    if (problem.inside[i]) {
      ASSERT_EQ(result.values[0][i], 0.0);
    }
}

TEST(Membrane, ResidualMeasuresTheDiscreteEquation) {
  const MembraneProblem problem = problemOn(48, twoDiscs(48), 1);
  std::vector<Field> values = solveMembraneDirect(problem).values;
  EXPECT_LE(membraneResidual(problem, values)[0], 1e-12);
  const std::size_t center = std::size_t(24) * 48 + 12;
  ASSERT_TRUE(problem.inside[center]);
  values[0][center] += 1e-3;
  EXPECT_GE(membraneResidual(problem, values)[0], 1e-6);
}

// (f) Bad input is refused with a message, never a crash.
template <typename F>
std::string invalidArgumentMessage(F&& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no std::invalid_argument";
}

TEST(Membrane, RefusesBadInput) {
  const MembraneProblem good = problemOn(32, disc(32), 3);
  auto solveWith = [](const MembraneProblem& p, const MembraneOptions& o = {}) {
    return [p, o] { solveMembrane(p, o); };
  };

  MembraneProblem nearBorder = good;
  nearBorder.inside[std::size_t(16) * 32 + 1] = 1;
  EXPECT_NE(invalidArgumentMessage(solveWith(nearBorder)).find("border"), std::string::npos);
  EXPECT_NE(invalidArgumentMessage([&] { solveMembraneDirect(nearBorder); }).find("border"),
            std::string::npos);

  // Two nodes from the border is allowed, in both modes.
  MembraneProblem atTwo = good;
  atTwo.inside[std::size_t(16) * 32 + 2] = 1;
  atTwo.inside[std::size_t(29) * 32 + 16] = 1;
  EXPECT_TRUE(solveMembrane(atTwo).converged);
  atTwo.continuity = MembraneContinuity::C0;
  EXPECT_TRUE(solveMembrane(atTwo).converged);

  MembraneProblem empty = good;
  std::fill(empty.inside.begin(), empty.inside.end(), 0);
  EXPECT_NE(invalidArgumentMessage(solveWith(empty)).find("empty"), std::string::npos);

  MembraneOptions twoGuesses;
  twoGuesses.initialGuess = {good.channels[0], good.channels[1]};
  EXPECT_NE(invalidArgumentMessage(solveWith(good, twoGuesses)).find("channels"),
            std::string::npos);

  MembraneProblem shortChannel = good;
  shortChannel.channels[1].pop_back();
  EXPECT_NE(invalidArgumentMessage(solveWith(shortChannel)).find("channel 1"), std::string::npos);

  MembraneProblem noChannels = good;
  noChannels.channels.clear();
  EXPECT_NE(invalidArgumentMessage(solveWith(noChannels)).find("no channels"), std::string::npos);

  MembraneProblem wrongMask = good;
  wrongMask.inside.pop_back();
  EXPECT_NE(invalidArgumentMessage(solveWith(wrongMask)).find("mask"), std::string::npos);

  MembraneProblem tiny = good;
  tiny.width = tiny.height = 4;
  EXPECT_NE(invalidArgumentMessage(solveWith(tiny)).find("5 x 5"), std::string::npos);

  MembraneProblem notFinite = good;
  const auto roles = classifyMembraneNodes(32, 32, good.inside, MembraneContinuity::C1);
  const auto fixed = std::find(roles.begin(), roles.end(), MembraneNode::Fixed) - roles.begin();
  notFinite.channels[2][std::size_t(fixed)] = std::numeric_limits<double>::infinity();
  EXPECT_NE(invalidArgumentMessage(solveWith(notFinite)).find("not finite"), std::string::npos);

  MembraneOptions badTolerance;
  badTolerance.tolerance = 0;
  EXPECT_NE(invalidArgumentMessage(solveWith(good, badTolerance)).find("tolerance"),
            std::string::npos);
  MembraneOptions badThreshold;
  badThreshold.vulkanMinUnknowns = -1;
  EXPECT_NE(invalidArgumentMessage(solveWith(good, badThreshold)).find("vulkanMinUnknowns"),
            std::string::npos);
  MembraneOptions badSettings;
  badSettings.multigrid.smootherRatio = 1;
  EXPECT_NE(invalidArgumentMessage(solveWith(good, badSettings)).find("multigrid"),
            std::string::npos);
  EXPECT_NE(invalidArgumentMessage([&] {
              classifyMembraneNodes(32, 32, nearBorder.inside, MembraneContinuity::C0);
            }).find("border"),
            std::string::npos);
}

// The coarse operators are the Galerkin products R A P of the masked B-spline transfers, row by
// row, including the rows the mask cuts short; and they are symmetric.
TEST(MembraneMultigrid, CoarseOperatorsAreSymmetricGalerkinProducts) {
  using namespace membrane_detail;
  const MembraneHierarchy hierarchy(64, 64, annulusWithNotch(64), MembraneContinuity::C1, {});
  const auto& levels = hierarchy.levels();
  ASSERT_GE(levels.size(), 3u);
  for (std::size_t l = 0; l + 1 < levels.size(); ++l) {
    const Level& fine = levels[l];
    const Level& coarse = levels[l + 1];
    EXPECT_FALSE(coarse.customRows.empty()) << "level " << l + 1;
    const auto n = Eigen::Index(coarse.unknowns.size());
    Eigen::MatrixXd operatorMatrix(n, n), galerkinMatrix(n, n);
    std::vector<double> unit(coarse.grid.size(), 0.0), column(coarse.grid.size()),
        restricted(coarse.grid.size()), prolonged(fine.grid.size()), applied(fine.grid.size());
    for (Eigen::Index j = 0; j < n; ++j) {
      unit[std::size_t(coarse.unknowns[std::size_t(j)])] = 1;
      applyOperator(coarse, unit.data(), column.data());
      std::fill(prolonged.begin(), prolonged.end(), 0.0);
      prolongAdd(coarse, fine, unit.data(), prolonged.data());
      applyOperator(fine, prolonged.data(), applied.data());
      restrictToCoarse(fine, coarse, applied.data(), restricted.data());
      for (Eigen::Index i = 0; i < n; ++i) {
        operatorMatrix(i, j) = column[std::size_t(coarse.unknowns[std::size_t(i)])];
        galerkinMatrix(i, j) = restricted[std::size_t(coarse.unknowns[std::size_t(i)])];
      }
      unit[std::size_t(coarse.unknowns[std::size_t(j)])] = 0;
    }
    const double scale = operatorMatrix.cwiseAbs().maxCoeff();
    EXPECT_LE((operatorMatrix - galerkinMatrix).cwiseAbs().maxCoeff(), 1e-12 * scale)
        << "level " << l + 1;
    EXPECT_LE((operatorMatrix - operatorMatrix.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale)
        << "level " << l + 1;
  }
}

// Random values on the level's unknowns, zero elsewhere, as the kernels expect.
std::vector<float> randomOnUnknowns(const membrane_detail::Level& level, std::mt19937& random) {
  std::uniform_real_distribution<float> value(-1, 1);
  std::vector<float> v(level.grid.size(), 0.0f);
  for (int node : level.unknowns)
    v[std::size_t(node)] = value(random);
  return v;
}

// max |a - b| relative to max |b|.
double relativeDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double difference = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference = std::max(difference, std::abs(double(a[i]) - double(b[i])));
    scale = std::max(scale, std::abs(double(b[i])));
  }
  return difference / scale;
}

// The finest level's kernels sum each node's written-out stencil in the loop that uses it; they
// give, bit for bit, what the stencil at each node (rowProduct) gives, for the plate and the
// Laplace stencil, and the residual also written over its right-hand side.
TEST(MembraneKernels, FinestLevelKernelsSumEachNodeAsItsRowProductDoes) {
  using namespace membrane_detail;
  std::mt19937 random(11);
  for (MembraneContinuity continuity : {MembraneContinuity::C1, MembraneContinuity::C0}) {
    const MembraneHierarchy hierarchy(64, 64, annulusWithNotch(64), continuity, {});
    const Level& level = hierarchy.levels().front();
    ASSERT_TRUE(level.customRows.empty());
    const std::vector<float> b = randomOnUnknowns(level, random);
    const std::vector<float> x = randomOnUnknowns(level, random);
    const std::vector<float> d = randomOnUnknowns(level, random);
    const float keep = 0.3f, gain = 0.37f;
    std::vector<float> residual(level.grid.size(), 0.0f), stepD(level.grid.size(), 0.0f),
        stepX(level.grid.size(), 0.0f);
    for (int node : level.unknowns) {
      const auto i = std::size_t(node);
      residual[i] = b[i] - rowProduct(level, x.data(), node);
      stepD[i] = keep * d[i] + gain * level.single.inverseDiagonal[i] * residual[i];
      stepX[i] = x[i] + stepD[i];
    }

    std::vector<float> out(level.grid.size(), 0.0f);
    subtractOperator(level, b.data(), x.data(), out.data());
    EXPECT_EQ(out, residual);
    std::vector<float> inPlace = b;
    subtractOperator(level, inPlace.data(), x.data(), inPlace.data());
    EXPECT_EQ(inPlace, residual);
    std::vector<float> nextD = d, nextX(level.grid.size(), 0.0f);
    chebyshevStep(level, b.data(), x.data(), nextX.data(), nextD.data(), keep, gain);
    EXPECT_EQ(nextD, stepD);
    EXPECT_EQ(nextX, stepX);
  }
}

// The Vulkan passes compute what the CPU kernels do: on the finest level (the plate stencil) and
// on coarse levels (49-point stencils, custom rows along the boundary of Q).
TEST(MembraneVulkan, KernelsMatchTheCpuKernels) {
  using namespace membrane_detail;
  if (!VulkanLevelKernels::available())
    GTEST_SKIP() << "Vulkan is unavailable: " << gpu::VulkanContext::unavailableReason();
  const MembraneHierarchy hierarchy(96, 96, annulusWithNotch(96), MembraneContinuity::C1, {});
  std::mt19937 random(7);
  for (std::size_t l = 0; l < 3; ++l) {
    const Level& level = hierarchy.levels()[l];
    ASSERT_EQ(level.customRows.empty(), l == 0);
    VulkanLevelKernels vulkan(level);
    const std::vector<float> b = randomOnUnknowns(level, random);
    const std::vector<float> x = randomOnUnknowns(level, random);
    std::vector<float> cpu(level.grid.size(), 0.0f), gpu(level.grid.size(), 0.0f);

    applyOperator(level, x.data(), cpu.data());
    vulkan.apply(x.data(), gpu.data());
    EXPECT_LE(relativeDifference(gpu, cpu), 1e-6) << "A x on level " << l;

    subtractOperator(level, b.data(), x.data(), cpu.data());
    vulkan.subtract(b.data(), x.data(), gpu.data());
    EXPECT_LE(relativeDifference(gpu, cpu), 1e-6) << "b - A x on level " << l;

    // Three smoother steps, as smoothing from a nonzero x runs them.
    const ChebyshevStep steps[] = {{0.0f, 0.4f}, {0.3f, 0.5f}, {0.45f, 0.6f}};
    std::vector<float> cpuX = x, cpuD(level.grid.size(), 0.0f), other(level.grid.size(), 0.0f);
    for (const ChebyshevStep& step : steps) {
      chebyshevStep(level, b.data(), cpuX.data(), other.data(), cpuD.data(), step.keep, step.gain);
      std::swap(cpuX, other);
    }
    std::vector<float> gpuX = x, gpuD(level.grid.size(), 0.0f);
    vulkan.chebyshev(b.data(), gpuX.data(), gpuD.data(), steps);
    EXPECT_LE(relativeDifference(gpuX, cpuX), 1e-6) << "smoothed x on level " << l;
    EXPECT_LE(relativeDifference(gpuD, cpuD), 1e-6) << "last step on level " << l;
  }
}

// With the Vulkan kernel the cycle's smoother and residuals run on the device: on the finest level
// only (the default threshold at 96^2) or on every level but the coarsest. CG converges as with
// the CPU kernel, in as many iterations, to the same solution.
class MembraneVulkanSolve : public ::testing::TestWithParam<Shape> {};

TEST_P(MembraneVulkanSolve, AgreesWithTheCpuKernel) {
  if (!membrane_detail::VulkanLevelKernels::available())
    GTEST_SKIP() << "Vulkan is unavailable: " << gpu::VulkanContext::unavailableReason();
  const int n = 96;
  const MembraneProblem problem = problemOn(n, GetParam().make(n));
  MembraneOptions options;
  options.tolerance = 1e-9;
  const MembraneResult cpu = solveMembrane(problem, options);
  ASSERT_TRUE(cpu.converged);
  EXPECT_EQ(cpu.kernel, MembraneKernel::Cpu);
  EXPECT_EQ(cpu.vulkanLevels, 0);
  options.kernel = MembraneKernel::Vulkan;
  options.hierarchy = cpu.hierarchy;
  for (const int minUnknowns : {MembraneOptions().vulkanMinUnknowns, 0}) {
    options.vulkanMinUnknowns = minUnknowns;
    const MembraneResult vulkan = solveMembrane(problem, options);
    ASSERT_TRUE(vulkan.converged) << "residual " << vulkan.residual;
    EXPECT_EQ(vulkan.kernel, MembraneKernel::Vulkan);
    ASSERT_GE(vulkan.levels, 3);
    EXPECT_EQ(vulkan.vulkanLevels, minUnknowns == 0 ? vulkan.levels - 1 : 1);
    EXPECT_NEAR(vulkan.iterations, cpu.iterations, 2);
    double largest = 0;
    for (std::size_t c = 0; c < problem.channels.size(); ++c) {
      const double difference = relativeError(problem, vulkan.values[c], cpu.values[c]);
      EXPECT_LE(difference, 1e-6) << "channel " << c;
      largest = std::max(largest, difference);
    }
    const std::string suffix = "_" + std::to_string(vulkan.vulkanLevels) + "_levels";
    RecordProperty("iterations_cpu", cpu.iterations);
    RecordProperty("iterations_vulkan" + suffix, vulkan.iterations);
    std::ostringstream difference;
    difference << largest;
    RecordProperty("relative_difference" + suffix, difference.str());
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, MembraneVulkanSolve,
                         ::testing::Values(Shape{"disc", disc},
                                           Shape{"annulus_with_notch", annulusWithNotch},
                                           Shape{"channel", channel}),
                         [](const auto& info) { return std::string(info.param.name); });

// The channels' threads share the hierarchy's device kernels: the values do not depend on the
// thread count, and a second solve on the hierarchy reuses its kernels (one upload).
TEST(MembraneVulkan, ReusesTheHierarchyKernelsAcrossThreadsAndSolves) {
  if (!membrane_detail::VulkanLevelKernels::available())
    GTEST_SKIP() << "Vulkan is unavailable: " << gpu::VulkanContext::unavailableReason();
  const MembraneProblem problem = problemOn(64, notchedDisc(64));
  MembraneOptions options;
  options.kernel = MembraneKernel::Vulkan;
  options.threads = 1;
  const MembraneResult single = solveMembrane(problem, options);
  const membrane_detail::VulkanCycleKernels* kernels = &single.hierarchy->vulkanKernels();
  options.threads = 3;
  options.hierarchy = single.hierarchy;
  const MembraneResult threaded = solveMembrane(problem, options);
  EXPECT_TRUE(threaded.hierarchyReused);
  EXPECT_EQ(&threaded.hierarchy->vulkanKernels(), kernels);
  EXPECT_EQ(threaded.values, single.values);
  EXPECT_EQ(threaded.iterations, single.iterations);
}

TEST(MembraneVulkan, DescribesTheSharedDevice) {
  const MembraneVulkanDevice found = membraneVulkanDevice();
  EXPECT_EQ(found.available, found.unavailableReason.empty());
  EXPECT_EQ(found.available, !found.name.empty());
}

// The node's data: outside Q the membrane carries the draft onto the target.

std::shared_ptr<Parameterization> heightField(int n,
                                              const std::function<double(double, double)>& z) {
  return test::heightFieldParameterization(n, z);
}

Strokes disc(Eigen::Vector2d centre, double radius) {
  Strokes strokes;
  strokes.dabs.push_back({centre, radius, false});
  return strokes;
}

Field2D solveForNode(const Region2D& region, const Parameterization& source, const TriMesh& draft,
                     const Parameterization& target, MembraneContinuity continuity) {
  const DomainLocator sourceLocator(source), targetLocator(target);
  const MembraneSetup setup =
      membraneSetup(region, source, draft, sourceLocator, targetLocator, continuity);
  MembraneOptions options;
  options.tolerance = 1e-10;
  const MembraneResult result = solveMembrane(setup.problem, options);
  EXPECT_TRUE(result.converged);
  return membraneField(region, setup, result.values);
}

// Mean angle between the normals of the two faces at each edge of the seam strip that it shares
// with the target or the patch.
double meanSeamNormalJump(const StitchResult& stitched) {
  const TriMesh& mesh = stitched.mesh;
  const int gapStart = int(mesh.n_faces() - stitched.gapTriangles);
  auto normal = [&](TriMesh::FaceHandle f) {
    std::vector<Eigen::Vector3d> c;
    for (auto v : mesh.fv_range(f))
      c.emplace_back(mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]);
    return Eigen::Vector3d((c[1] - c[0]).cross(c[2] - c[0]).normalized());
  };
  double sum = 0;
  int count = 0;
  for (auto e : mesh.edges()) {
    const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
    const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
    if (!f0.is_valid() || !f1.is_valid() || (f0.idx() >= gapStart) == (f1.idx() >= gapStart))
      continue;
    sum += std::acos(std::clamp(normal(f0).dot(normal(f1)), -1.0, 1.0));
    ++count;
  }
  return sum / count;
}

TEST(MembraneNodeData, AConstantGapIsClosedByAConstantOffset) {
  auto source = heightField(24, [](double, double) { return 0.0; });
  auto target = heightField(20, [](double, double) { return 0.0; });
  const Region2D region = paintRegion(disc({0.1, 0}, 0.5), *source, *target, RoiOptions{64}).region;
  TriMesh draft = source->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[2] += 0.25;  // the draft floats above the target
  for (auto continuity : {MembraneContinuity::C1, MembraneContinuity::C0}) {
    const Field2D field = solveForNode(region, *source, draft, *target, continuity);
    for (int v : region.sourceVertices) {
      Eigen::Vector3d offset;
      ASSERT_TRUE(field.sample(source->uv[std::size_t(v)], offset)) << v;
      EXPECT_NEAR((offset - Eigen::Vector3d(0, 0, -0.25)).norm(), 0, 1e-8);
    }
  }
}

// A brush keeps the locators' answers per grid node from dab to dab: the setup is the one a fresh
// call makes, bit for bit, while the stroke grows and the draft moves; a new grid starts afresh.
TEST(MembraneNodeData, KeptLocationsGiveWhatFreshOnesGive) {
  auto source = heightField(24, [](double x, double y) { return 0.1 * x * y; });
  auto target = heightField(20, [](double x, double) { return 0.05 * x; });
  const DomainLocator sourceLocator(*source), targetLocator(*target);
  TriMesh draft = source->canvas->surface;
  MembraneLocations kept;
  Strokes strokes = disc({-0.3, 0}, 0.2);
  for (int dab = 0; dab < 4; ++dab) {
    const int gridSize = dab < 3 ? 64 : 48;
    const Region2D region = paintRegion(strokes, *source, *target, RoiOptions{gridSize}).region;
    for (auto v : draft.vertices())
      draft.point(v)[2] += 0.01 * (dab + 1);
    const MembraneSetup withKept = membraneSetup(region, *source, draft, sourceLocator,
                                                 targetLocator, MembraneContinuity::C1, &kept);
    const MembraneSetup fresh =
        membraneSetup(region, *source, draft, sourceLocator, targetLocator, MembraneContinuity::C1);
    EXPECT_EQ(withKept.problem.channels, fresh.problem.channels) << "dab " << dab;
    EXPECT_EQ(withKept.defined, fresh.defined);
    EXPECT_EQ(kept.grid, region.grid);
    strokes.dabs.push_back({{-0.3 + 0.15 * (dab + 1), 0.05 * dab}, 0.2, false});
  }
}

// On the mountain's terrain, lifted along its up axis: the membrane brings the lifted draft back
// down by the same amount, whatever the mesh's irregular triangles.
TEST(MembraneNodeData, ClosesAConstantGapOnARealTerrain) {
  auto terrain = test::terrainParameterization();
  Eigen::Vector2d lo = terrain->uv.front(), hi = lo;
  for (const auto& u : terrain->uv) {
    lo = lo.cwiseMin(u);
    hi = hi.cwiseMax(u);
  }
  const Region2D region =
      paintRegion(disc((lo + hi) / 2, 0.2 * (hi - lo).minCoeff()), *terrain, *terrain).region;
  ASSERT_FALSE(region.empty());
  TriMesh draft = terrain->canvas->surface;
  for (auto v : draft.vertices())
    draft.point(v)[1] += 1.5;
  const Field2D field = solveForNode(region, *terrain, draft, *terrain, MembraneContinuity::C1);
  for (int v : region.sourceVertices) {
    Eigen::Vector3d offset;
    ASSERT_TRUE(field.sample(terrain->uv[std::size_t(v)], offset)) << v;
    EXPECT_NEAR((offset - Eigen::Vector3d(0, -1.5, 0)).norm(), 0, 1e-7);
  }
}

// The paper's Fig. 10a-b with G = 0: a flat patch pasted into a curved target is bent by the
// membrane alone. With the derivative constraints the fill meets the target tangentially; without
// them only its position matches, and the normals jump across the seam.
TEST(MembraneNodeData, DerivativeConstraintsSmoothTheSeam) {
  const auto bowl = [](double x, double y) { return 0.6 * (x * x + y * y) + 0.3 * x; };
  auto source = heightField(40, [](double, double) { return 0.0; });
  auto target = heightField(40, bowl);
  const Region2D region = paintRegion(disc({0, 0}, 0.55), *source, *target, RoiOptions{96}).region;
  TriMesh zero = source->canvas->surface;
  for (auto v : zero.vertices())
    zero.point(v) = {0, 0, 0};
  double jump[2];
  int k = 0;
  for (auto continuity : {MembraneContinuity::C1, MembraneContinuity::C0}) {
    const Field2D field = solveForNode(region, *source, zero, *target, continuity);
    const StitchResult stitched = stitchPaste(region, *source, zero, &field, *target);
    EXPECT_EQ(meshStats(stitched.mesh).boundaryLoops, 1u);
    jump[k++] = meanSeamNormalJump(stitched);
  }
  EXPECT_LT(jump[0], 0.5 * jump[1]) << "C1 " << jump[0] << " rad, C0 " << jump[1] << " rad";
  RecordProperty("seam_jump_c1", std::to_string(jump[0]));
  RecordProperty("seam_jump_c0", std::to_string(jump[1]));
}

TEST(MembraneNode, AnEmptyRegionGivesAnUndefinedField) {
  const NodeType* type = test::registry().find("geobrush.membrane");
  ASSERT_TRUE(type);
  auto param = heightField(8, [](double, double) { return 0.0; });
  auto region =
      std::make_shared<Region2D>(paintRegion(Strokes(), *param, *param, RoiOptions{32}).region);
  test::DirectContext ctx(*type, {{"region", region},
                                  {"source", param},
                                  {"draft", std::make_shared<const Mesh>(param->canvas->surface)},
                                  {"target", param}});
  type->create()->compute(ctx);
  auto field = std::dynamic_pointer_cast<const Field2D>(ctx.outputs["offset"]);
  ASSERT_TRUE(field);
  EXPECT_EQ(std::count(field->defined.begin(), field->defined.end(), 1), 0);
}

// Dab after dab on one node: each result is the one a fresh node computes, bit for bit, and the
// canvases' locators are derived once. The kernel is named, so the notes do not depend on the
// machine's Vulkan device.
TEST(MembraneNode, ADabAfterAnotherGivesWhatAFreshNodeGives) {
  const NodeType* type = test::registry().find("geobrush.membrane");
  ASSERT_TRUE(type);
  auto source = heightField(30, [](double, double) { return 0.0; });
  auto target = heightField(30, [](double x, double y) { return 0.2 * x * y; });
  auto draft = std::make_shared<const Mesh>(source->canvas->surface);
  auto node = type->create();
  const auto derived = std::make_shared<DerivedStore>();
  Strokes strokes = disc({0, 0}, 0.4);
  for (int dab = 0; dab < 3; ++dab) {
    SCOPED_TRACE(dab);
    auto region =
        std::make_shared<Region2D>(paintRegion(strokes, *source, *target, RoiOptions{64}).region);
    const std::map<std::string, ValuePtr, std::less<>> inputs = {
        {"region", region}, {"source", source}, {"draft", draft}, {"target", target}};
    const ParamMap params = {{"kernel", std::string("cpu")}};
    test::DirectContext ctx(*type, inputs, params, derived);
    node->compute(ctx);
    EXPECT_FALSE(node->usedHistory());
    const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
    ASSERT_TRUE(report);
    EXPECT_LE(report->values.at("relative_residual"), 1e-7);
    EXPECT_EQ(report->notes, std::vector<std::string>{"kernel: cpu"});
    test::DirectContext freshCtx(*type, inputs, params);
    type->create()->compute(freshCtx);
    EXPECT_EQ(ctx.outputs["offset"]->contentHash(), freshCtx.outputs["offset"]->contentHash());
    EXPECT_EQ(derived->builds(), 2u);  // the source's and the target's locators
    strokes.dabs.push_back({{0.38, 0.05 * dab}, 0.06, false});  // a small dab at the edge
  }
}

// Dragging the target canvas: the source's locator stays, the target's is derived anew; each
// field solves its own target's data.
TEST(MembraneNode, FollowsAMovedTarget) {
  const NodeType* type = test::registry().find("geobrush.membrane");
  ASSERT_TRUE(type);
  auto source = heightField(30, [](double, double) { return 0.0; });
  auto draft = std::make_shared<const Mesh>(source->canvas->surface);
  auto node = type->create();
  const auto derived = std::make_shared<DerivedStore>();
  const Strokes strokes = disc({0, 0}, 0.4);
  for (int move = 0; move < 3; ++move) {
    SCOPED_TRACE(move);
    const double tilt = 0.1 * move;
    auto target = heightField(30, [tilt](double x, double y) { return 0.2 * x * y + tilt * x; });
    auto region =
        std::make_shared<Region2D>(paintRegion(strokes, *source, *target, RoiOptions{64}).region);
    test::DirectContext ctx(
        *type, {{"region", region}, {"source", source}, {"draft", draft}, {"target", target}}, {},
        derived);
    node->compute(ctx);
    const auto offset = std::dynamic_pointer_cast<const Field2D>(ctx.outputs["offset"]);
    ASSERT_TRUE(offset);
    EXPECT_EQ(derived->builds(), std::uint64_t(2 + move));
    const Field2D fresh =
        solveForNode(*region, *source, draft->surface, *target, MembraneContinuity::C1);
    double largest = 0;
    for (std::size_t n = 0; n < fresh.values.size(); ++n)
      if (fresh.defined[n]) largest = std::max(largest, fresh.values[n].norm());
    ASSERT_GT(largest, 0.01);
    for (std::size_t n = 0; n < fresh.values.size(); ++n) {
      if (!fresh.defined[n]) continue;
      EXPECT_NEAR((offset->values[n] - fresh.values[n]).norm(), 0, 1e-4 * largest) << n;
    }
  }
}

// One dab through the node with the given params.
struct NodeRun {
  std::shared_ptr<const Field2D> offset;
  std::shared_ptr<const Metrics> report;
};

NodeRun runMembraneNode(const ParamMap& params) {
  const NodeType* type = test::registry().find("geobrush.membrane");
  EXPECT_TRUE(type);
  auto source = heightField(30, [](double, double) { return 0.0; });
  auto target = heightField(30, [](double x, double y) { return 0.2 * x * y + 0.1 * x; });
  auto region = std::make_shared<Region2D>(
      paintRegion(disc({0.05, 0}, 0.45), *source, *target, RoiOptions{64}).region);
  test::DirectContext ctx(*type,
                          {{"region", region},
                           {"source", source},
                           {"draft", std::make_shared<const Mesh>(source->canvas->surface)},
                           {"target", target}},
                          params);
  type->create()->compute(ctx);
  return {std::dynamic_pointer_cast<const Field2D>(ctx.outputs["offset"]),
          std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"])};
}

TEST(MembraneNode, VulkanKernelAgreesWithTheCpuKernel) {
  const MembraneVulkanDevice device = membraneVulkanDevice();
  if (!device.available) GTEST_SKIP() << "Vulkan is unavailable: " << device.unavailableReason;
  const NodeRun cpu = runMembraneNode({{"kernel", std::string("cpu")}, {"tolerance", 1e-10}});
  const NodeRun vulkan = runMembraneNode({{"kernel", std::string("vulkan")}, {"tolerance", 1e-10}});
  ASSERT_TRUE(cpu.offset && vulkan.offset && cpu.report && vulkan.report);
  EXPECT_EQ(cpu.report->notes, std::vector<std::string>{"kernel: cpu"});
  EXPECT_EQ(vulkan.report->notes, std::vector<std::string>{"kernel: vulkan (" + device.name + ")"});
  ASSERT_EQ(vulkan.offset->defined, cpu.offset->defined);
  std::size_t defined = 0;
  for (std::size_t n = 0; n < cpu.offset->values.size(); ++n) {
    if (!cpu.offset->defined[n]) continue;
    ++defined;
    EXPECT_NEAR((vulkan.offset->values[n] - cpu.offset->values[n]).norm(), 0, 1e-6) << n;
  }
  EXPECT_GT(defined, 100u);
}

// On lavapipe (a CPU device) auto runs the CPU kernel; on a GPU, Vulkan.
// auto runs the CPU kernel on every device, a GPU included (see chooseKernel).
TEST(MembraneNode, AutoRunsTheCpuKernel) {
  const NodeRun run = runMembraneNode({});  // kernel = auto, the default
  ASSERT_TRUE(run.report);
  EXPECT_EQ(run.report->notes, std::vector<std::string>{"kernel: cpu"});
}

// Runs where there is no Vulkan device (GEOBRUSH_VK_DEVICE=none forces that).
TEST(MembraneNode, VulkanWithoutADeviceIsAnErrorOnTheParam) {
  const MembraneVulkanDevice device = membraneVulkanDevice();
  if (device.available) GTEST_SKIP() << "a Vulkan device exists: " << device.name;
  EXPECT_EQ(runMembraneNode({}).report->notes, std::vector<std::string>{"kernel: cpu"});
  try {
    runMembraneNode({{"kernel", std::string("vulkan")}});
    ADD_FAILURE() << "kernel = vulkan was accepted without a device";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'kernel'");
  }
  MembraneOptions options;
  options.kernel = MembraneKernel::Vulkan;
  EXPECT_THROW(solveMembrane(problemOn(32, disc(32)), options), std::runtime_error);
}

// A solve that cannot reach the tolerance in the iterations allowed fails on the node, naming
// both.
TEST(MembraneNode, ASolveShortOfTheToleranceIsAnError) {
  try {
    runMembraneNode({{"tolerance", 1e-12}, {"max_iterations", 1}});
    ADD_FAILURE() << "one iteration reached 1e-12";
  } catch (const NodeError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("did not reach the tolerance 1e-12 within 1 iterations"),
              std::string::npos)
        << message;
  }
  EXPECT_TRUE(runMembraneNode({{"max_iterations", 100}}).offset);
}

TEST(MembraneNode, RefusesAnUnknownKernel) {
  const NodeType* type = test::registry().find("geobrush.membrane");
  ASSERT_TRUE(type);
  const auto decl = std::find_if(type->params.begin(), type->params.end(),
                                 [](const ParamDecl& p) { return p.name == "kernel"; });
  ASSERT_NE(decl, type->params.end());
  EXPECT_EQ(decl->choices, (std::vector<std::string>{"auto", "cpu", "vulkan"}));
  EXPECT_TRUE(checkParam(*decl, ParamValue(std::string("gpu"))).has_value());
  // A value that reaches the node anyway is refused by name.
  try {
    runMembraneNode({{"kernel", std::string("gpu")}});
    ADD_FAILURE() << "kernel = gpu was accepted";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'kernel'");
    EXPECT_NE(std::string(e.what()).find("gpu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace geobrush
