// renderMeshes() on bunny_small at 800×600: the Vulkan backend (on whatever
// device the shared context found) against the CPU rasterizer twin.
#include <benchmark/benchmark.h>

#include "geobrush/gpu/vulkan_context.hpp"
#include "geobrush/render.hpp"
#include "mesh_checks.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

MeshPtr readShared(const std::string& name) {
  TriMesh surface;
  const auto path = test::meshPath(name);
  if (!OpenMesh::IO::read_mesh(surface, path.string()))
    throw std::runtime_error("cannot read " + path.string());
  return std::make_shared<const Mesh>(std::move(surface));
}

MeshPtr bunny() {
  static const MeshPtr mesh = readShared("bunny_small.obj");
  return mesh;
}

void renderBunny(benchmark::State& state, RenderBackend backend, bool wireframe) {
  if (backend == RenderBackend::Vulkan && !gpu::VulkanContext::shared()) {
    state.SkipWithError(
        ("Vulkan is unavailable: " + gpu::VulkanContext::unavailableReason()).c_str());
    return;
  }
  const std::vector<RenderItem> items = {{bunny(), {0.78f, 0.78f, 0.80f}, wireframe}};
  RenderOptions options;
  options.width = 800;
  options.height = 600;
  options.backend = backend;
  // The first Vulkan render builds the pipeline once per process; leave it out.
  state.SetLabel(renderMeshes(items, options).device);
  for (auto _ : state)
    benchmark::DoNotOptimize(renderMeshes(items, options));
  state.SetItemsProcessed(state.iterations() * std::int64_t(bunny()->surface.n_faces()));
}

// Real time: lavapipe renders on its own threads, which CPU time misses.
BENCHMARK_CAPTURE(renderBunny, vulkan, RenderBackend::Vulkan, false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(renderBunny, cpu, RenderBackend::Cpu, false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(renderBunny, vulkan_wireframe, RenderBackend::Vulkan, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(renderBunny, cpu_wireframe, RenderBackend::Cpu, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// An orbit on the armadillo (29k faces) at a view's size, a degree a frame, on the CPU
// rasterizer: a Renderer keeping the mesh's geometry between frames, as a view does, against
// renderMeshes preparing it for every frame.
void orbitArmadillo(benchmark::State& state, bool kept) {
  static const MeshPtr armadillo = readShared("armadillo.obj");
  const std::vector<RenderItem> items = {{armadillo}};
  RenderOptions options;
  options.width = 700;
  options.height = 450;
  options.backend = RenderBackend::Cpu;
  Renderer renderer;
  int frame = 0;
  for (auto _ : state) {
    options.view.azimuthDeg = frame++ % 360;
    benchmark::DoNotOptimize(kept ? renderer.render(items, options) : renderMeshes(items, options));
  }
}
BENCHMARK_CAPTURE(orbitArmadillo, render_meshes, false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(orbitArmadillo, renderer, true)->Unit(benchmark::kMillisecond)->UseRealTime();

// A view of the brush's target (a 163,842-vertex sphere, 327,680 faces) orbited at a view's size
// through a Renderer keeping its geometry, on each backend: what a studio view pays a frame (on
// the CPU rasterizer, which the views take).
void orbitTarget(benchmark::State& state, RenderBackend backend) {
  if (backend == RenderBackend::Vulkan && !gpu::VulkanContext::shared()) {
    state.SkipWithError(
        ("Vulkan is unavailable: " + gpu::VulkanContext::unavailableReason()).c_str());
    return;
  }
  static const MeshPtr sphere = std::make_shared<const Mesh>(test::icosphere(7));
  const std::vector<RenderItem> items = {{sphere}};
  RenderOptions options;
  options.width = 700;
  options.height = 450;
  options.backend = backend;
  Renderer renderer;
  // The first frame builds the geometry (and, on Vulkan, the pipeline); leave it out.
  state.SetLabel(renderer.render(items, options).device);
  int frame = 1;
  for (auto _ : state) {
    options.view.azimuthDeg = frame++ % 360;
    benchmark::DoNotOptimize(renderer.render(items, options));
  }
}
BENCHMARK_CAPTURE(orbitTarget, vulkan, RenderBackend::Vulkan)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(orbitTarget, cpu, RenderBackend::Cpu)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace geobrush
