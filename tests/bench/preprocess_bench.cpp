// The source side of the GeoBrush preprocess on a 50k-vertex canvas: canvas
// growth, generalized DEM, cage build and the Green-coordinates precompute,
// each timed on its own and all together (goal: <= 0.5 s on 2 cores).
// The surface is a 224 x 224 height field with relief, the whole of it painted.
#include <benchmark/benchmark.h>

#include <cmath>

#include "cage_build.hpp"
#include "canvas_grow.hpp"
#include "gc_warp.hpp"
#include "geobrush/exponential_map.hpp"

using namespace geobrush;

namespace {

constexpr int kSide = 223;  // quads per side: 224^2 = 50176 vertices

MeshPtr reliefPatch() {
  TriMesh mesh;
  for (int j = 0; j <= kSide; ++j)
    for (int i = 0; i <= kSide; ++i) {
      const double x = 2.0 * i / kSide - 1, y = 2.0 * j / kSide - 1;
      const double z =
          0.3 * std::exp(-4 * (x * x + y * y)) + 0.02 * std::sin(17 * x) * std::cos(13 * y);
      mesh.add_vertex({x, y, z});
    }
  auto vh = [](int i, int j) { return TriMesh::VertexHandle(j * (kSide + 1) + i); };
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      mesh.add_face(vh(i, j), vh(i + 1, j), vh(i + 1, j + 1));
      mesh.add_face(vh(i, j), vh(i + 1, j + 1), vh(i, j + 1));
    }
  return std::make_shared<const Mesh>(std::move(mesh));
}

struct Stages {
  MeshPtr mesh = reliefPatch();
  CanvasGrowOptions grow;
  Stages() {
    grow.origin = {0, 0, 0.3};
    grow.dabs.push_back({Eigen::Vector3d::Zero(), 10.0});
  }
  std::shared_ptr<Canvas> canvas() const {
    return std::make_shared<Canvas>(growCanvas(mesh, grow));
  }
  std::shared_ptr<Parameterization> map(const std::shared_ptr<Canvas>& canvas) const {
    DemResult dem = discreteExponentialMap(*canvas, DemOptions{});
    auto param = std::make_shared<Parameterization>();
    param->canvas = canvas;
    param->uv = std::move(dem.uv);
    param->normal = std::move(dem.normal);
    param->origin = dem.origin;
    param->reversedFaces = std::move(dem.reversedFaces);
    return param;
  }
};

std::vector<Eigen::Vector3d> points(const TriMesh& mesh) {
  std::vector<Eigen::Vector3d> result;
  for (auto v : mesh.vertices())
    result.emplace_back(mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]);
  return result;
}

void BM_CanvasGrow(benchmark::State& state) {
  Stages stages;
  for (auto _ : state)
    benchmark::DoNotOptimize(stages.canvas());
}

void BM_GeneralizedDem(benchmark::State& state) {
  Stages stages;
  auto canvas = stages.canvas();
  for (auto _ : state)
    benchmark::DoNotOptimize(stages.map(canvas));
  state.counters["vertices"] = double(canvas->surface.n_vertices());
}

void BM_CageBuild(benchmark::State& state) {
  Stages stages;
  auto param = stages.map(stages.canvas());
  for (auto _ : state)
    benchmark::DoNotOptimize(buildCage(*param));
}

void BM_GreenCoordinates(benchmark::State& state) {
  Stages stages;
  auto canvas = stages.canvas();
  const Cage cage = buildCage(*stages.map(canvas)).cage;
  const auto canvasPoints = points(canvas->surface);
  for (auto _ : state)
    benchmark::DoNotOptimize(computeGreenCoordinates(cage.mesh, canvasPoints));
  state.counters["cage_faces"] = double(cage.mesh.n_faces());
}

void BM_WholeSourcePreprocess(benchmark::State& state) {
  Stages stages;
  for (auto _ : state) {
    auto canvas = stages.canvas();
    const Cage cage = buildCage(*stages.map(canvas)).cage;
    benchmark::DoNotOptimize(computeGreenCoordinates(cage.mesh, points(canvas->surface)));
  }
}

}  // namespace

BENCHMARK(BM_CanvasGrow)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_GeneralizedDem)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_CageBuild)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_GreenCoordinates)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_WholeSourcePreprocess)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
