// The texture copy on the mountain canvas (../shared/data/meshes/mountain.obj, 50562 faces), as
// source and target, at N = 512 and 1024:
//   BM_FaceList/N              the CPU's part of a rasterization: snapping, depth order, per-tile
//                              face lists;
//   BM_Rasterize/N/kernel      a canvas' whole texture (face list included) with the CPU twin
//                              (kernel:0) or the Vulkan kernel (kernel:1; uploads and readback
//                              included), side by side in one process;
//   BM_DabCopy/N               what a new dab costs: the copy with both textures derived before
//                              (a ten-dab stroke across the canvas, dabs of radius 2).
#include <benchmark/benchmark.h>

#include <memory>

#include "canvas_fixtures.hpp"
#include "texture_raster_vulkan.hpp"
#include "texture_roi.hpp"

namespace {

using namespace geobrush;

const Parameterization& mountain() {
  static const std::shared_ptr<Parameterization> param = test::terrainParameterization();
  return *param;
}

void BM_FaceList(benchmark::State& state) {
  const DomainGrid grid = textureGrid(mountain(), int(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(rasterFaces(mountain(), grid));
}
BENCHMARK(BM_FaceList)
    ->ArgName("N")
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Rasterize(benchmark::State& state) {
  const auto kernel = state.range(1) == 1 ? TextureKernel::Vulkan : TextureKernel::Cpu;
  if (kernel == TextureKernel::Vulkan && !textureRasterVulkanAvailable()) {
    state.SkipWithError("Vulkan is unavailable");
    return;
  }
  if (kernel == TextureKernel::Vulkan) state.SetLabel(textureRasterVulkanDevice());
  const DomainGrid grid = textureGrid(mountain(), int(state.range(0)));
  rasterize(mountain(), grid, kernel);  // the pipeline is made once per process
  for (auto _ : state)
    benchmark::DoNotOptimize(rasterize(mountain(), grid, kernel));
}
BENCHMARK(BM_Rasterize)
    ->ArgNames({"N", "kernel"})
    ->ArgsProduct({{512, 1024}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_DabCopy(benchmark::State& state) {
  TextureRoiOptions options;
  options.textureSize = int(state.range(0));
  const auto source = textureSourceSide(mountain(), options);
  const auto target = textureTargetSide(mountain(), source->texture.grid, options.kernel);
  const DomainLocator locator(mountain());
  Strokes strokes;
  for (int d = 0; d < 10; ++d)
    strokes.dabs.push_back({Eigen::Vector2d(-8 + 1.6 * d, 0.5 * d), 2.0, false});
  for (auto _ : state)
    benchmark::DoNotOptimize(
        copyTexels(strokes, mountain(), mountain(), *source, *target, locator));
}
BENCHMARK(BM_DabCopy)
    ->ArgName("N")
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
