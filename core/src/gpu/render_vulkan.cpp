// The Vulkan backend of renderMeshes(): one draw of the prepared triangles
// into an offscreen RGBA8 + D32 target, copied into a host-visible buffer.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "../render_scene.hpp"
#include "geobrush/gpu/vulkan_context.hpp"
#include "geobrush/shaders/mesh_frag.h"
#include "geobrush/shaders/mesh_vert.h"

namespace geobrush::detail {
namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkShaderStageFlags kPushStages =
    VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

// Everything that does not depend on the image size; built once per context.
struct MeshPipeline {
  gpu::RenderPass renderPass;
  gpu::PipelineLayout layout;
  gpu::Pipeline pipeline;
};

gpu::RenderPass createRenderPass(const gpu::VulkanContext& context) {
  VkAttachmentDescription attachments[2] = {};
  attachments[0].format = kColorFormat;
  attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  attachments[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  attachments[1] = attachments[0];
  attachments[1].format = kDepthFormat;
  attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;

  const VkAttachmentReference colorRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &colorRef;
  subpass.pDepthStencilAttachment = &depthRef;

  // The copy to the readback buffer waits for the colour writes.
  VkSubpassDependency toCopy{};
  toCopy.srcSubpass = 0;
  toCopy.dstSubpass = VK_SUBPASS_EXTERNAL;
  toCopy.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  toCopy.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  toCopy.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  toCopy.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;

  auto info = gpu::makeInfo<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
  info.attachmentCount = 2;
  info.pAttachments = attachments;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 1;
  info.pDependencies = &toCopy;
  VkRenderPass pass = VK_NULL_HANDLE;
  gpu::check(vkCreateRenderPass(context.device(), &info, nullptr, &pass), "vkCreateRenderPass");
  return {context.device(), pass};
}

gpu::PipelineLayout createLayout(const gpu::VulkanContext& context) {
  const VkPushConstantRange range{kPushStages, 0, sizeof(ShadingConstants)};
  auto info =
      gpu::makeInfo<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  info.pushConstantRangeCount = 1;
  info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  gpu::check(vkCreatePipelineLayout(context.device(), &info, nullptr, &layout),
             "vkCreatePipelineLayout");
  return {context.device(), layout};
}

gpu::Pipeline createPipeline(const gpu::VulkanContext& context, VkRenderPass renderPass,
                             VkPipelineLayout layout) {
  const gpu::ShaderModule vertexShader = context.createShaderModule(mesh_vert);
  const gpu::ShaderModule fragmentShader = context.createShaderModule(mesh_frag);
  VkPipelineShaderStageCreateInfo stages[2];
  for (auto [stage, bit, module] : {std::tuple{0, VK_SHADER_STAGE_VERTEX_BIT, vertexShader.get()},
                                    {1, VK_SHADER_STAGE_FRAGMENT_BIT, fragmentShader.get()}}) {
    stages[stage] = gpu::makeInfo<VkPipelineShaderStageCreateInfo>(
        VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    stages[stage].stage = bit;
    stages[stage].module = module;
    stages[stage].pName = "main";
  }

  const VkVertexInputBindingDescription binding{0, sizeof(SceneVertex),
                                                VK_VERTEX_INPUT_RATE_VERTEX};
  constexpr std::uint32_t kLineBytes = sizeof(SceneVertex::edgeLines[0]);
  const VkVertexInputAttributeDescription attributes[7] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, position)},
      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, normal)},
      {2, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, color)},
      {3, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, edgeLines)},
      {4, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, edgeLines) + kLineBytes},
      {5, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SceneVertex, edgeLines) + 2 * kLineBytes},
      {6, 0, VK_FORMAT_R32_SFLOAT, offsetof(SceneVertex, wireframe)}};
  auto vertexInput = gpu::makeInfo<VkPipelineVertexInputStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  vertexInput.vertexBindingDescriptionCount = 1;
  vertexInput.pVertexBindingDescriptions = &binding;
  vertexInput.vertexAttributeDescriptionCount = 7;
  vertexInput.pVertexAttributeDescriptions = attributes;

  auto inputAssembly = gpu::makeInfo<VkPipelineInputAssemblyStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  inputAssembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  auto viewport = gpu::makeInfo<VkPipelineViewportStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  // Two-sided: nothing is culled; facing was resolved in the normals.
  auto raster = gpu::makeInfo<VkPipelineRasterizationStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  auto multisample = gpu::makeInfo<VkPipelineMultisampleStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  auto depth = gpu::makeInfo<VkPipelineDepthStencilStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS;
  VkPipelineColorBlendAttachmentState blendAttachment{};
  blendAttachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                   VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  auto blend = gpu::makeInfo<VkPipelineColorBlendStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  blend.attachmentCount = 1;
  blend.pAttachments = &blendAttachment;
  const VkDynamicState dynamicStates[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  auto dynamic = gpu::makeInfo<VkPipelineDynamicStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamicStates;

  auto info =
      gpu::makeInfo<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vertexInput;
  info.pInputAssemblyState = &inputAssembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = layout;
  info.renderPass = renderPass;
  VkPipeline pipeline = VK_NULL_HANDLE;
  gpu::check(
      vkCreateGraphicsPipelines(context.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
      "vkCreateGraphicsPipelines");
  return {context.device(), pipeline};
}

std::unique_ptr<MeshPipeline> createMeshPipeline(const gpu::VulkanContext& context) {
  VkFormatProperties depthSupport;
  vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), kDepthFormat, &depthSupport);
  if (!(depthSupport.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
    throw std::runtime_error("Vulkan: " + context.deviceName() +
                             " cannot render into a D32 depth buffer");
  auto mesh = std::make_unique<MeshPipeline>();
  mesh->renderPass = createRenderPass(context);
  mesh->layout = createLayout(context);
  mesh->pipeline = createPipeline(context, mesh->renderPass.get(), mesh->layout.get());
  return mesh;
}

gpu::Framebuffer createFramebuffer(const gpu::VulkanContext& context, VkRenderPass renderPass,
                                   const gpu::Image2D& color, const gpu::Image2D& depth) {
  const VkImageView views[2] = {color.view(), depth.view()};
  auto info = gpu::makeInfo<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
  info.renderPass = renderPass;
  info.attachmentCount = 2;
  info.pAttachments = views;
  info.width = color.extent().width;
  info.height = color.extent().height;
  info.layers = 1;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  gpu::check(vkCreateFramebuffer(context.device(), &info, nullptr, &framebuffer),
             "vkCreateFramebuffer");
  return {context.device(), framebuffer};
}

void recordDraw(VkCommandBuffer commands, const Scene& scene, const MeshPipeline& mesh,
                VkFramebuffer framebuffer, const gpu::Buffer& vertices) {
  const VkExtent2D extent{std::uint32_t(scene.width), std::uint32_t(scene.height)};
  // k/255 converts back to exactly k, so background pixels match the CPU twin.
  VkClearValue clears[2] = {};
  for (int c = 0; c < 4; ++c)
    clears[0].color.float32[c] = scene.background[c] / 255.0f;
  clears[1].depthStencil = {1.0f, 0};
  auto begin = gpu::makeInfo<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
  begin.renderPass = mesh.renderPass.get();
  begin.framebuffer = framebuffer;
  begin.renderArea = {{0, 0}, extent};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);

  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, mesh.pipeline.get());
  const VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0, 1};
  const VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(commands, 0, 1, &viewport);
  vkCmdSetScissor(commands, 0, 1, &scissor);
  vkCmdPushConstants(commands, mesh.layout.get(), kPushStages, 0, sizeof(ShadingConstants),
                     &scene.constants);
  const VkBuffer buffer = vertices.handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(commands, 0, 1, &buffer, &offset);
  vkCmdDraw(commands, std::uint32_t(3 * scene.triangles()), 1, 0, 0);
  vkCmdEndRenderPass(commands);
}

void recordReadback(VkCommandBuffer commands, const gpu::Image2D& color,
                    const gpu::Buffer& readback) {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {color.extent().width, color.extent().height, 1};
  vkCmdCopyImageToBuffer(commands, color.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         readback.handle(), 1, &region);
  auto toHost = gpu::makeInfo<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &toHost, 0, nullptr, 0, nullptr);
}

}  // namespace

Image renderVulkan(const Scene& scene, gpu::VulkanContext& context) {
  const MeshPipeline& mesh = context.cached<MeshPipeline>(
      "geobrush.render.mesh", [&context] { return createMeshPipeline(context); });
  const auto width = std::uint32_t(scene.width);
  const auto height = std::uint32_t(scene.height);

  const VkDeviceSize vertexBytes = 3 * scene.triangles() * sizeof(SceneVertex);
  const gpu::Buffer vertices = context.createBuffer(vertexBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  writeCorners(scene, static_cast<SceneVertex*>(vertices.mapped()));

  const gpu::Image2D color =
      context.createImage(width, height, kColorFormat,
                          VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                          VK_IMAGE_ASPECT_COLOR_BIT);
  const gpu::Image2D depth =
      context.createImage(width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                          VK_IMAGE_ASPECT_DEPTH_BIT);
  const gpu::Framebuffer framebuffer =
      createFramebuffer(context, mesh.renderPass.get(), color, depth);
  const gpu::Buffer readback =
      context.createBuffer(4ull * width * height, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);

  context.submit([&](VkCommandBuffer commands) {
    recordDraw(commands, scene, mesh, framebuffer.get(), vertices);
    recordReadback(commands, color, readback);
  });

  // Tightly packed RGBA8 rows, top row first, as Image stores them.
  Image image(scene.width, scene.height);
  std::memcpy(image.rgba.data(), readback.mapped(), image.rgba.size());
  return image;
}

}  // namespace geobrush::detail
