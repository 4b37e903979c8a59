// The offset membrane at brush resolution: a 256^2 grid, a disc-like region with a notch (45100
// unknowns), three channels (x, y, z), the default tolerance (an estimated energy-norm error of
// 1e-6).
//   BM_MembraneCold/threads      a solve with no previous one (a nested-iteration start), hierarchy
//                                built;
//   BM_MembraneAfterDab/threads  the next dab: Q grew, the hierarchy is updated from the previous
//                                one, and the solve starts from the previous dab's solution;
//   BM_MembraneHierarchy/update/threads
//                                the hierarchy alone, built from scratch (0) or updated from the
//                                previous region's (1);
//   BM_MembraneDirect            the sparse LDL^T reference: factor once, solve three channels;
//   BM_MembraneKernel/kernel:0 (cpu), BM_MembraneKernel/kernel:1 (vulkan)
//                                a solve from zero on a hierarchy built beforehand (its Vulkan
//                                kernels made and uploaded once), channels on the hardware's
//                                threads, with the cycle's smoother and residuals on the CPU or as
//                                Vulkan passes (on the levels with at least 4096 unknowns: 2 of
//                                6 here): with BM_MembraneDirect, the three ways to solve one grid
//                                in one run;
//   BM_VulkanKernelsSetup        making the hierarchy's Vulkan kernels (descriptor sets and
//                                coefficient uploads; the pipeline is made once per process);
//   BM_SmootherCpu/level, BM_SmootherVulkan/level
//                                three Chebyshev smoother steps on one multigrid level, on the CPU
//                                and as Vulkan passes in one submission (uploads and readback
//                                included).
// The membrane benchmarks report `speedup`: the direct solve's median time (measured once in the
// same process) over their own wall time per iteration.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "membrane.hpp"
#include "membrane_levels.hpp"
#include "membrane_vulkan.hpp"

namespace {

using geobrush::MembraneOptions;
using geobrush::MembraneProblem;

constexpr int kSize = 256;

std::vector<std::uint8_t> region(double dabRadius) {
  std::vector<std::uint8_t> inside(std::size_t(kSize) * kSize, 0);
  const double center = (kSize - 1) / 2.0, radius = kSize / 2.0 - 4;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const double dx = x - center, dy = y - center;
      const bool notch = dx > 0 && std::abs(dy) < kSize / 20.0;
      const bool dab = std::hypot(dx - 0.15 * kSize, dy) < dabRadius;
      inside[std::size_t(y) * kSize + std::size_t(x)] =
          (std::hypot(dx, dy) < radius && !notch) || dab;
    }
  return inside;
}

// Q before the dab, or after it (the dab fills the inner end of the notch).
const MembraneProblem& problem(bool afterDab) {
  static const auto make = [](bool dab) {
    MembraneProblem p;
    p.width = p.height = kSize;
    p.inside = region(dab ? kSize / 12.0 : 0);
    for (int c = 0; c < 3; ++c) {
      std::vector<double> field(std::size_t(kSize) * kSize);
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const double u = double(x) / kSize, v = double(y) / kSize;
          field[std::size_t(y) * kSize + std::size_t(x)] =
              std::sin(3 * u + c) * std::cos(2 * v) + (c + 1) * u * u - v;
        }
      p.channels.push_back(std::move(field));
    }
    return p;
  };
  static const MembraneProblem before = make(false), after = make(true);
  return afterDab ? after : before;
}

double directMedianSeconds() {
  static const double median = [] {
    std::vector<double> times;
    for (int run = 0; run < 5; ++run) {
      const auto start = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(geobrush::solveMembraneDirect(problem(false)).values.data());
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
  }();
  return median;
}

// Runs `solve` as the benchmark's loop and reports the direct solve's median over the wall time
// per iteration.
template <typename Solve>
void timeAgainstDirect(benchmark::State& state, Solve&& solve) {
  const double direct = directMedianSeconds();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state)
    solve();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["speedup"] = direct * double(state.iterations()) / seconds;
}

void BM_MembraneCold(benchmark::State& state) {
  MembraneOptions options;
  options.threads = int(state.range(0));
  int iterations = 0;
  timeAgainstDirect(state, [&] {
    const auto result = geobrush::solveMembrane(problem(false), options);
    iterations = result.iterations;
    benchmark::DoNotOptimize(result.values.data());
  });
  state.counters["cg_iterations"] = iterations;
}
BENCHMARK(BM_MembraneCold)
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(7)
    ->ReportAggregatesOnly();

void BM_MembraneAfterDab(benchmark::State& state) {
  MembraneOptions options;
  options.threads = int(state.range(0));
  const auto previous = geobrush::solveMembrane(problem(false), options);
  options.initialGuess = previous.values;
  options.hierarchy = previous.hierarchy;
  int iterations = 0;
  timeAgainstDirect(state, [&] {
    const auto result = geobrush::solveMembrane(problem(true), options);
    iterations = result.iterations;
    benchmark::DoNotOptimize(result.values.data());
  });
  state.counters["cg_iterations"] = iterations;
}
BENCHMARK(BM_MembraneAfterDab)
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(7)
    ->ReportAggregatesOnly();

// The hierarchy alone: built from scratch (update:0), or updated from the previous region's
// (update:1) as the next dab does, on `threads` threads.
void BM_MembraneHierarchy(benchmark::State& state) {
  const MembraneProblem& before = problem(false);
  const MembraneProblem& after = problem(true);
  const bool update = state.range(0) != 0;
  const int threads = int(state.range(1));
  const geobrush::MembraneHierarchy previous(before.width, before.height, before.inside,
                                             before.continuity, {});
  for (auto _ : state) {
    const geobrush::MembraneHierarchy built(after.width, after.height, after.inside,
                                            after.continuity, {}, update ? &previous : nullptr,
                                            threads);
    benchmark::DoNotOptimize(built.levels().data());
  }
}
BENCHMARK(BM_MembraneHierarchy)
    ->ArgNames({"update", "threads"})
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_MembraneDirect(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(geobrush::solveMembraneDirect(problem(false)).values.data());
}
BENCHMARK(BM_MembraneDirect)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();

void BM_MembraneKernel(benchmark::State& state) {
  MembraneOptions options;
  options.kernel = geobrush::MembraneKernel(state.range(0));
  if (options.kernel == geobrush::MembraneKernel::Vulkan &&
      !geobrush::membrane_detail::VulkanLevelKernels::available()) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  // Built (and its device kernels made) outside the timed loop; a local, so that it is destroyed
  // before the Vulkan context at exit.
  options.hierarchy = geobrush::solveMembrane(problem(false), options).hierarchy;
  int iterations = 0, deviceLevels = 0;
  timeAgainstDirect(state, [&] {
    const auto result = geobrush::solveMembrane(problem(false), options);
    iterations = result.iterations;
    deviceLevels = result.vulkanLevels;
    benchmark::DoNotOptimize(result.values.data());
  });
  state.counters["cg_iterations"] = iterations;
  state.counters["vulkan_levels"] = deviceLevels;
  state.SetLabel(geobrush::membraneKernelName(options.kernel));
}
BENCHMARK(BM_MembraneKernel)
    ->ArgName("kernel")
    ->Arg(int(geobrush::MembraneKernel::Cpu))
    ->Arg(int(geobrush::MembraneKernel::Vulkan))
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly();

const geobrush::MembraneHierarchy& hierarchy() {
  static const auto built = geobrush::solveMembrane(problem(false)).hierarchy;
  return *built;
}

constexpr geobrush::membrane_detail::ChebyshevStep kSteps[] = {
    {0.0f, 0.4f}, {0.3f, 0.5f}, {0.45f, 0.6f}};

std::vector<float> onesOnUnknowns(const geobrush::membrane_detail::Level& level) {
  std::vector<float> v(level.grid.size(), 0.0f);
  for (int node : level.unknowns)
    v[std::size_t(node)] = 1.0f;
  return v;
}

void BM_SmootherCpu(benchmark::State& state) {
  const auto& level = hierarchy().levels()[std::size_t(state.range(0))];
  const std::vector<float> b = onesOnUnknowns(level);
  std::vector<float> x(b.size(), 0.0f), other(b.size(), 0.0f), d(b.size(), 0.0f);
  for (auto _ : state)
    for (const auto& step : kSteps) {
      geobrush::membrane_detail::chebyshevStep(level, b.data(), x.data(), other.data(), d.data(),
                                               step.keep, step.gain);
      std::swap(x, other);
    }
  state.counters["unknowns"] = double(level.unknowns.size());
}
BENCHMARK(BM_SmootherCpu)->Arg(0)->Arg(1)->Arg(4)->Unit(benchmark::kMicrosecond);

// Making the Vulkan kernels of the 256^2 hierarchy: what a Vulkan solve on a new hierarchy (the
// next dab) pays once. The first iteration also makes the process's pipeline.
void BM_VulkanKernelsSetup(benchmark::State& state) {
  if (!geobrush::membrane_detail::VulkanLevelKernels::available()) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  for (auto _ : state)
    geobrush::membrane_detail::VulkanCycleKernels kernels(hierarchy());
  state.counters["levels"] = double(hierarchy().levels().size() - 1);
}
BENCHMARK(BM_VulkanKernelsSetup)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_SmootherVulkan(benchmark::State& state) {
  using geobrush::membrane_detail::VulkanLevelKernels;
  if (!VulkanLevelKernels::available()) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  const auto& level = hierarchy().levels()[std::size_t(state.range(0))];
  VulkanLevelKernels kernels(level);
  const std::vector<float> b = onesOnUnknowns(level);
  std::vector<float> x(b.size(), 0.0f), d(b.size(), 0.0f);
  for (auto _ : state)
    kernels.chebyshev(b.data(), x.data(), d.data(), kSteps);
  state.counters["unknowns"] = double(level.unknowns.size());
}
BENCHMARK(BM_SmootherVulkan)->Arg(0)->Arg(1)->Arg(4)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
