// The projective target stamp as run on every drag of the target canvas, on the same target and
// source as dem_bench's BM_TargetDem (a 163k-vertex subdivided sphere, a disc spanning about 10%
// of its circumference), so that the two target maps compare. The StampTarget (nearest-point
// search) is built once per target, as the node keeps it; BM_PrepareStampTarget times that.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "dpm_target.hpp"
#include "mesh_checks.hpp"

namespace {

const geobrush::MeshPtr& targetSphere() {
  static const geobrush::MeshPtr sphere =
      std::make_shared<const geobrush::Mesh>(geobrush::test::icosphere(7));  // 163842 vertices
  return sphere;
}

void BM_ProjectiveStamp(benchmark::State& state) {
  const geobrush::MeshPtr& sphere = targetSphere();
  // A 40 x 40 source canvas over [-1, 1]^2.
  std::vector<Eigen::Vector2d> source;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i)
      source.emplace_back(-1 + i / 20.0, -1 + j / 20.0);
  geobrush::ProjectiveStampOptions o;
  o.origin = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  o.scale = 0.35;  // disc radius 1.77 x 0.35 = 0.62 on the unit sphere
  const geobrush::StampTarget target(sphere);
  std::size_t vertices = 0;
  for (auto _ : state) {
    const auto stamp = geobrush::projectiveStamp(target, source, o);
    vertices = stamp.uv.size();
    benchmark::DoNotOptimize(stamp.uv.data());
  }
  state.counters["canvas_vertices"] = static_cast<double>(vertices);
  state.counters["mesh_vertices"] = static_cast<double>(sphere->surface.n_vertices());
}
BENCHMARK(BM_ProjectiveStamp)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(7)
    ->ReportAggregatesOnly();

void BM_PrepareStampTarget(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(geobrush::StampTarget(targetSphere()).diagonal());
}
BENCHMARK(BM_PrepareStampTarget)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly();

}  // namespace
