// The texture copy's rasterization as a Vulkan compute kernel (shaders/texture_raster.comp): the
// CPU's per-tile face lists in, per texel the face id + 1 and two integer edge weights out, equal
// bit for bit to rasterizeCpu (texture_roi.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "texture_roi.hpp"

namespace geobrush {

// Whether the shared Vulkan context has a device, and why not when it has none.
bool textureRasterVulkanAvailable();
std::string textureRasterVulkanUnavailableReason();
// The device's name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"; empty without one.
std::string textureRasterVulkanDevice();

// rasterizeCpu on the device: one submission (uploads and readback included). Throws
// std::runtime_error without a device or when a Vulkan call fails.
void rasterizeVulkan(const RasterFaces& faces, std::vector<std::uint32_t>& face,
                     std::vector<std::int64_t>& weight);

}  // namespace geobrush
