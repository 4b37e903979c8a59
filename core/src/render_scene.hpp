// What both renderers draw: the meshes expanded to independent triangles,
// with smooth normals already turned towards the camera, plus the camera and
// the lights. prepareScene() builds it once per render, so the Vulkan and CPU
// backends share every decision but rasterization and float rounding.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geobrush/render.hpp"

namespace geobrush::gpu {
class VulkanContext;
}

namespace geobrush::detail {

// One triangle corner, laid out as shaders/mesh.vert reads it.
struct SceneVertex {
  std::array<float, 3> position;  // relative to the centre of the bounding box
  std::array<float, 3> normal;    // unit; flipped where the triangle faces away
  std::array<float, 3> color;     // linear RGB
  // The triangle's edges (opposite corners 0, 1, 2) as lines a x + b y + c = 0
  // in window pixels with a² + b² = 1, so |a x + b y + c| is the distance in
  // pixels; the same in all three corners.
  std::array<std::array<float, 3>, 3> edgeLines;
  float wireframe;  // 1 where the edges are drawn, else 0
};

// The push-constant block of shaders/mesh.vert and shaders/mesh.frag.
struct ShadingConstants {
  // Column-major, to Vulkan clip space: y down, depth 0 (near) to 1 (far).
  std::array<float, 16> viewProjection;
  std::array<float, 4> headlight;  // xyz: unit direction towards the light; w: weight
  std::array<float, 4> fillLight;  // as headlight
  std::array<float, 4> material;   // x: ambient weight; y: grey level of wireframe edges
};
static_assert(sizeof(ShadingConstants) == 112, "must match the GLSL push-constant block");

struct Scene {
  int width = 0;
  int height = 0;
  std::vector<SceneVertex> vertices;  // three per triangle, in draw order
  ShadingConstants constants{};
  std::array<std::uint8_t, 4> background{};  // RGBA8
};

// Checks items and options, throwing std::runtime_error that names the
// culprit, and builds the scene.
Scene prepareScene(const std::vector<RenderItem>& items, const RenderOptions& options);

// The rounding to 8 bits that the Vulkan colour attachment applies too.
std::uint8_t toUnorm8(float value);

Image renderCpu(const Scene& scene);
Image renderVulkan(const Scene& scene, gpu::VulkanContext& context);

}  // namespace geobrush::detail
