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

using DescriptorPool = gpu::DeviceHandle<VkDescriptorPool, vkDestroyDescriptorPool>;

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

gpu::Buffer hostBuffer(const gpu::VulkanContext& context, std::size_t bytes) {
  return context.createBuffer(
      VkDeviceSize(std::max<std::size_t>(bytes, 4)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
}

gpu::Buffer upload(const gpu::VulkanContext& context, const std::vector<std::int32_t>& values) {
  gpu::Buffer buffer = hostBuffer(context, values.size() * sizeof(std::int32_t));
  if (!values.empty())
    std::memcpy(buffer.mapped(), values.data(), values.size() * sizeof(std::int32_t));
  return buffer;
}

// One call's buffers and the descriptor set that binds them.
struct Call {
  std::array<gpu::Buffer, kBindings> buffers;
  DescriptorPool pool;
  VkDescriptorSet set = VK_NULL_HANDLE;  // freed with the pool
};

void bindBuffers(VkDevice device, VkDescriptorSetLayout setLayout, Call& call) {
  const VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindings};
  auto poolInfo =
      gpu::makeInfo<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &poolSize;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  gpu::check(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
  call.pool = {device, pool};
  auto allocInfo =
      gpu::makeInfo<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  allocInfo.descriptorPool = pool;
  allocInfo.descriptorSetCount = 1;
  allocInfo.pSetLayouts = &setLayout;
  gpu::check(vkAllocateDescriptorSets(device, &allocInfo, &call.set), "vkAllocateDescriptorSets");
  std::array<VkDescriptorBufferInfo, kBindings> infos{};
  std::array<VkWriteDescriptorSet, kBindings> writes{};
  for (std::uint32_t b = 0; b < kBindings; ++b) {
    infos[b] = {call.buffers[b].handle(), 0, VK_WHOLE_SIZE};
    writes[b] = gpu::makeInfo<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[b].dstSet = call.set;
    writes[b].dstBinding = b;
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  vkUpdateDescriptorSets(device, kBindings, writes.data(), 0, nullptr);
}

void dispatch(gpu::VulkanContext& context, const gpu::ComputeProgram& program, const Call& call,
              const Raster& raster) {
  context.submit([&](VkCommandBuffer commands) {
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline.get());
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout.get(), 0, 1,
                            &call.set, 0, nullptr);
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

bool textureRasterVulkanOnGpu() {
  const gpu::VulkanContext* context = gpu::VulkanContext::shared();
  return context != nullptr && !context->isCpu();
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
  call.buffers[3] = hostBuffer(*context, texels * kTexelWords * sizeof(std::uint32_t));
  bindBuffers(context->device(), program.setLayout.get(), call);
  dispatch(*context, program, call, {faces.size, faces.tilesPerSide, kSubtexelBits});
  readTexels(call.buffers[3], texels, face, weight);
}

}  // namespace geobrush
