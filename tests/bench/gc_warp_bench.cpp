// Green coordinates precompute: ns per (point, cage face) for the parallel version with per-face
// and per-edge data computed once, against the naive single-threaded (point, face) loop, on
// 20k points in a 588-face cage (a box with 7 x 7 squares a side, bent so that no symmetry
// helps). The counter "ns_per_point_face" is wall time per pair; compare the two rows.
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "gc_warp.hpp"
#include "mesh_checks.hpp"

using namespace geobrush;

namespace {

TriMesh bentBoxCage(int n) {
  TriMesh mesh = test::boxCage(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), n);
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    mesh.point(v) = {p[0] * (1 + 0.2 * p[1]), p[1], p[2] + 0.1 * p[0] * p[0]};
  }
  return mesh;
}

std::vector<Eigen::Vector3d> interiorPoints(int count) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.75, 0.75);
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(count));
  for (auto& p : points)
    p = {u(rng), u(rng), u(rng)};
  return points;
}

template <bool kNaive>
void BM_GreenCoordinates(benchmark::State& state) {
  const TriMesh cage = bentBoxCage(7);
  const auto points = interiorPoints(int(state.range(0)));
  GreenOptions options;
  options.threads = 2;
  for (auto _ : state) {
    auto result = kNaive ? computeGreenCoordinatesNaive(cage, points, options)
                         : computeGreenCoordinates(cage, points, options);
    benchmark::DoNotOptimize(result.phi.data());
  }
  const double pairs = double(points.size()) * double(cage.n_faces());
  state.counters["ns_per_point_face"] = benchmark::Counter(
      pairs * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["faces"] = double(cage.n_faces());
}

void BM_ApplyGreenCoordinates(benchmark::State& state) {
  const TriMesh cage = bentBoxCage(7);
  const auto points = interiorPoints(int(state.range(0)));
  const auto gc = computeGreenCoordinates(cage, points);
  TriMesh moved = cage;
  for (auto v : moved.vertices())
    moved.set_point(v, moved.point(v) * 1.5 + TriMesh::Point(0, 0, 0.2 * moved.point(v)[0]));
  for (auto _ : state)
    benchmark::DoNotOptimize(applyGreenCoordinates(gc.phi, gc.psi, cage, moved).data());
}

}  // namespace

BENCHMARK_TEMPLATE(BM_GreenCoordinates, false)
    ->Name("BM_GreenCoordinates/parallel_2_threads")
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK_TEMPLATE(BM_GreenCoordinates, true)
    ->Name("BM_GreenCoordinates/naive_1_thread")
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(BM_ApplyGreenCoordinates)->Arg(20000)->Unit(benchmark::kMillisecond)->UseRealTime();
