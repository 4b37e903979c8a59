// Green coordinates precompute: ns per (point, cage face) for the parallel version with per-face
// and per-edge data computed once, against the naive single-threaded (point, face) loop, on
// 20k points in a 588-face cage (a box with 7 x 7 squares a side, bent so that no symmetry
// helps). The counter "ns_per_point_face" is wall time per pair; compare the two rows.
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "gc_warp.hpp"

using namespace geobrush;

namespace {

TriMesh bentBoxCage(int n) {
  TriMesh mesh;
  std::map<std::array<int, 3>, TriMesh::VertexHandle> lattice;
  auto vertex = [&](std::array<int, 3> ijk) {
    auto [it, added] = lattice.try_emplace(ijk);
    if (added) {
      const double x = 2.0 * ijk[0] / n - 1, y = 2.0 * ijk[1] / n - 1, z = 2.0 * ijk[2] / n - 1;
      it->second = mesh.add_vertex({x * (1 + 0.2 * y), y, z + 0.1 * x * x});
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side : {0, n})
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> ijk{};
            ijk[std::size_t(axis)] = side;
            ijk[std::size_t(u)] = i + di;
            ijk[std::size_t(v)] = j + dj;
            return vertex(ijk);
          };
          const auto c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1), c01 = corner(0, 1);
          if (side == n) {
            mesh.add_face(c00, c10, c11);
            mesh.add_face(c00, c11, c01);
          } else {
            mesh.add_face(c00, c11, c10);
            mesh.add_face(c00, c01, c11);
          }
        }
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
