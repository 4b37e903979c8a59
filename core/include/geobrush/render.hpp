// Offscreen rendering of shaded meshes into an Image: Vulkan when a device
// is found (a GPU, else lavapipe), with a CPU rasterizer twin.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geobrush/image.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/param.hpp"

namespace geobrush {

struct RenderItem {
  MeshPtr mesh;
  Rgb color{0.78f, 0.78f, 0.80f};  // used where the mesh has no vertex colours
  bool wireframe = false;          // draw triangle edges over the shading
};

// An orbit camera around the bounding box of everything drawn.
struct RenderView {
  double azimuthDeg = 30;    // around +y, from +z towards +x
  double elevationDeg = 20;  // above the xz plane
  double fovDeg = 35;        // vertical field of view
  double zoom = 1;           // > 1 moves closer than the fitted distance
};

enum class RenderBackend { Auto, Vulkan, Cpu };

struct RenderOptions {
  int width = 800;
  int height = 600;
  RenderView view;
  Rgb background{1.0f, 1.0f, 1.0f};
  RenderBackend backend = RenderBackend::Auto;
};

struct RenderResult {
  Image image;
  std::string backend;  // "vulkan" or "cpu"
  std::string device;   // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or "cpu rasterizer"
};

// Throws std::runtime_error if nothing can be drawn (no faces, bad size) or
// the Vulkan backend was forced and is unavailable. With Auto, a failing
// Vulkan path falls back to the CPU rasterizer.
RenderResult renderMeshes(const std::vector<RenderItem>& items, const RenderOptions& options = {});

}  // namespace geobrush
