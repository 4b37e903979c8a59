// The texture copy's rasterization on Vulkan ("Mesh Geometric Editing Approach Based on GPU
// Texture": the CPU builds the face-id list, the GPU fills the texture).
#include "texture_raster_vulkan.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "geobrush/gpu/vulkan_context.hpp"
// The generated header needs <cstdint> first.
#include "geobrush/shaders/texture_raster_comp.h"

namespace geobrush {
namespace {

constexpr std::uint32_t kBindings = 4;  // faces, tileStart, tileFaces, texels
constexpr std::size_t kTexelWords = 5;  // face id + 1, two weights as (low, high) words

// The shader's push constants, field for field.
struct Raster {
  std::int32_t size, tilesPerSide, subtexelBits;
};

// The pipeline and its layouts, made once per process (lavapipe takes milliseconds to compile a
// pipeline), after the Vulkan context and so destroyed before it at exit.
// The process's program; a failed creation throws and is retried on the next call.
const gpu::ComputeProgram& sharedProgram(gpu::VulkanContext& context) {
  static std::mutex mutex;
  static std::unique_ptr<gpu::ComputeProgram> program;
  const std::lock_guard lock(mutex);
  if (!program)
    program = std::make_unique<gpu::ComputeProgram>(
        context.createComputeProgram(texture_raster_comp, kBindings, sizeof(Raster)));
  return *program;
}

gpu::Buffer upload(const gpu::VulkanContext& context, const std::vector<std::int32_t>& values) {
  gpu::Buffer buffer = context.createHostStorageBuffer(values.size() * sizeof(std::int32_t));
  if (!values.empty())
    std::memcpy(buffer.mapped(), values.data(), values.size() * sizeof(std::int32_t));
  return buffer;
}

// One call's buffers and the descriptor set that binds them.
struct Call {
  std::array<gpu::Buffer, kBindings> buffers;
  gpu::BoundBuffers bound;
};

void dispatch(gpu::VulkanContext& context, const gpu::ComputeProgram& program, const Call& call,
              const Raster& raster) {
  context.submit([&](VkCommandBuffer commands) {
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline.get());
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout.get(), 0, 1,
                            &call.bound.set, 0, nullptr);
    vkCmdPushConstants(commands, program.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       sizeof(Raster), &raster);
    // One workgroup per tile (local size kTextureTile x kTextureTile).
    vkCmdDispatch(commands, std::uint32_t(raster.tilesPerSide), std::uint32_t(raster.tilesPerSide),
                  1);
    auto barrier = gpu::makeInfo<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &barrier, 0, nullptr, 0, nullptr);
  });
}

void readTexels(const gpu::Buffer& texels, std::size_t count, std::vector<std::uint32_t>& face,
                std::vector<std::int64_t>& weight) {
  const auto* words = static_cast<const std::uint32_t*>(texels.mapped());
  face.resize(count);
  weight.resize(2 * count);
  for (std::size_t t = 0; t < count; ++t) {
    const std::uint32_t* w = words + t * kTexelWords;
    face[t] = w[0];
    weight[2 * t] = std::int64_t((std::uint64_t(w[2]) << 32) | w[1]);
    weight[2 * t + 1] = std::int64_t((std::uint64_t(w[4]) << 32) | w[3]);
  }
}

}  // namespace

bool textureRasterVulkanAvailable() {
  return gpu::VulkanContext::shared() != nullptr;
}

std::string textureRasterVulkanUnavailableReason() {
  return gpu::VulkanContext::unavailableReason();
}

std::string textureRasterVulkanDevice() {
  const gpu::VulkanContext* context = gpu::VulkanContext::shared();
  return context != nullptr ? context->deviceName() : std::string();
}

void rasterizeVulkan(const RasterFaces& faces, std::vector<std::uint32_t>& face,
                     std::vector<std::int64_t>& weight) {
  gpu::VulkanContext* context = gpu::VulkanContext::shared();
  if (context == nullptr) {
    std::string message = "texture_roi: no Vulkan device: ";
    message += gpu::VulkanContext::unavailableReason();
    throw std::runtime_error(message);
  }
  const gpu::ComputeProgram& program = sharedProgram(*context);
  const std::size_t texels = std::size_t(faces.size) * std::size_t(faces.size);
  Call call;
  call.buffers[0] = upload(*context, faces.faces);
  call.buffers[1] = upload(*context, faces.tileStart);
  call.buffers[2] = upload(*context, faces.tileFaces);
  call.buffers[3] = context->createHostStorageBuffer(texels * kTexelWords * sizeof(std::uint32_t));
  std::array<VkBuffer, kBindings> handles;
  for (std::size_t b = 0; b < kBindings; ++b)
    handles[b] = call.buffers[b].handle();
  call.bound = context->bindStorageBuffers(program, handles);
  dispatch(*context, program, call, {faces.size, faces.tilesPerSide, kSubtexelBits});
  readTexels(call.buffers[3], texels, face, weight);
}

}  // namespace geobrush
