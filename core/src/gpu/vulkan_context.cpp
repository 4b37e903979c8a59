#include "geobrush/gpu/vulkan_context.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <vector>

namespace geobrush::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string versionText(std::uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." +
         std::to_string(VK_API_VERSION_MINOR(version));
}

std::string_view typeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

int preference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

// "0: llvmpipe (...) [CPU], 1: ..." for messages about device choice.
std::string describe(std::span<const DeviceInfo> devices) {
  std::string text;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(i) + ": " + devices[i].name + " [" +
            std::string(typeName(devices[i].type)) + (devices[i].usable ? "" : ", unusable") + "]";
  }
  return text;
}

bool containsIgnoringCase(std::string_view text, std::string_view part) {
  const auto equal = [](unsigned char a, unsigned char b) {
    return std::tolower(a) == std::tolower(b);
  };
  return std::search(text.begin(), text.end(), part.begin(), part.end(), equal) != text.end();
}

std::optional<std::size_t> parseIndex(std::string_view text) {
  std::size_t index = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return index;
}

std::size_t forcedDevice(std::span<const DeviceInfo> devices, std::string_view forced) {
  const std::string prefix = "GEOBRUSH_VK_DEVICE=" + std::string(forced) + ": ";
  auto usableOrThrow = [&](std::size_t index) {
    if (!devices[index].usable)
      throw std::runtime_error(prefix + "device '" + devices[index].name +
                               "' lacks Vulkan 1.2 or a graphics+compute queue");
    return index;
  };
  if (auto index = parseIndex(forced)) {
    if (*index >= devices.size())
      throw std::runtime_error(prefix + "no device with that index (found " + describe(devices) +
                               ")");
    return usableOrThrow(*index);
  }
  std::optional<std::size_t> unusableMatch;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (!containsIgnoringCase(devices[i].name, forced)) continue;
    if (devices[i].usable) return i;
    unusableMatch = unusableMatch.value_or(i);
  }
  if (unusableMatch) return usableOrThrow(*unusableMatch);
  throw std::runtime_error(prefix + "matches no device (found " + describe(devices) + ")");
}

bool validationRequested() {
  const char* value = std::getenv("GEOBRUSH_VK_VALIDATION");
  return value != nullptr && std::string_view(value) == "1";
}

bool hasInstanceLayer(std::string_view name) {
  std::uint32_t count = 0;
  check(vkEnumerateInstanceLayerProperties(&count, nullptr), "vkEnumerateInstanceLayerProperties");
  std::vector<VkLayerProperties> layers(count);
  check(vkEnumerateInstanceLayerProperties(&count, layers.data()),
        "vkEnumerateInstanceLayerProperties");
  return std::ranges::any_of(layers, [&](const VkLayerProperties& layer) {
    return std::string_view(layer.layerName) == name;
  });
}

std::optional<std::uint32_t> graphicsComputeFamily(VkPhysicalDevice device) {
  std::uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  constexpr VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (std::uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & needed) == needed && families[i].queueCount > 0) return i;
  return std::nullopt;
}

}  // namespace

#define GEOBRUSH_VK_RESULT_CASE(name) \
  case name:                          \
    return #name;

std::string_view toString(VkResult result) {
  switch (result) {
    GEOBRUSH_VK_RESULT_CASE(VK_SUCCESS)
    GEOBRUSH_VK_RESULT_CASE(VK_NOT_READY)
    GEOBRUSH_VK_RESULT_CASE(VK_TIMEOUT)
    GEOBRUSH_VK_RESULT_CASE(VK_EVENT_SET)
    GEOBRUSH_VK_RESULT_CASE(VK_EVENT_RESET)
    GEOBRUSH_VK_RESULT_CASE(VK_INCOMPLETE)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_UNKNOWN)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_FRAGMENTATION)
    GEOBRUSH_VK_RESULT_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    default:
      return "unrecognised VkResult";
  }
}

#undef GEOBRUSH_VK_RESULT_CASE

void check(VkResult result, std::string_view call) {
  if (result == VK_SUCCESS) return;
  throw std::runtime_error("Vulkan: " + std::string(call) + " failed: " +
                           std::string(toString(result)) + " (" + std::to_string(result) + ")");
}

std::size_t pickDevice(std::span<const DeviceInfo> devices, std::string_view forced) {
  if (devices.empty()) throw std::runtime_error("no Vulkan device found");
  if (!forced.empty()) return forcedDevice(devices, forced);
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (devices[i].usable &&
        (!best || preference(devices[i].type) < preference(devices[*best].type)))
      best = i;
  }
  if (!best)
    throw std::runtime_error(
        "no Vulkan device has Vulkan 1.2 and a graphics+compute queue (found " + describe(devices) +
        ")");
  return *best;
}

namespace {
// Written once, while shared() creates the context.
std::string& unavailable() {
  static std::string reason;
  return reason;
}
}  // namespace

VulkanContext* VulkanContext::shared() {
  static const std::unique_ptr<VulkanContext> context = []() -> std::unique_ptr<VulkanContext> {
    try {
      return std::unique_ptr<VulkanContext>(new VulkanContext());
    } catch (const std::exception& error) {
      unavailable() = error.what();
      return nullptr;
    }
  }();
  return context.get();
}

const std::string& VulkanContext::unavailableReason() {
  shared();
  return unavailable();
}

VulkanContext::VulkanContext() {
  createInstance();
  choosePhysicalDevice();
  createDevice();
}

VulkanContext::~VulkanContext() {
  // Cached pipelines and the command pool go with the members; nothing may
  // still run on the device by then.
  if (device_) vkDeviceWaitIdle(device_.get());
}

void VulkanContext::createInstance() {
  std::uint32_t loaderVersion = 0;
  check(vkEnumerateInstanceVersion(&loaderVersion), "vkEnumerateInstanceVersion");
  if (loaderVersion < VK_API_VERSION_1_2)
    throw std::runtime_error("the Vulkan loader supports only Vulkan " +
                             versionText(loaderVersion) + "; 1.2 is needed");

  std::vector<const char*> layers;
  if (validationRequested()) {
    if (hasInstanceLayer(kValidationLayer))
      layers.push_back(kValidationLayer);
    else
      std::fprintf(stderr, "geobrush: GEOBRUSH_VK_VALIDATION=1 but %s is not installed\n",
                   kValidationLayer);
  }

  auto app = makeInfo<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "GeoBrush";
  app.pEngineName = "geobrush_core";
  app.apiVersion = VK_API_VERSION_1_2;
  auto info = makeInfo<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw std::runtime_error(
        "no Vulkan 1.2 driver is installed (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); "
        "Mesa's lavapipe (mesa-vulkan-drivers) runs on any CPU");
  check(result, "vkCreateInstance");
  instance_.reset(instance);
}

void VulkanContext::choosePhysicalDevice() {
  std::uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance_.get(), &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  check(vkEnumeratePhysicalDevices(instance_.get(), &count, devices.data()),
        "vkEnumeratePhysicalDevices");

  std::vector<DeviceInfo> infos;
  std::vector<std::optional<std::uint32_t>> families;
  for (VkPhysicalDevice device : devices) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(device, &properties);
    families.push_back(graphicsComputeFamily(device));
    infos.push_back({properties.deviceName, properties.deviceType,
                     properties.apiVersion >= VK_API_VERSION_1_2 && families.back().has_value()});
  }
  const char* forced = std::getenv("GEOBRUSH_VK_DEVICE");
  const std::size_t chosen = pickDevice(infos, forced ? forced : "");

  physicalDevice_ = devices[chosen];
  queueFamily_ = *families[chosen];
  vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
  deviceName_ = properties_.deviceName;
}

void VulkanContext::createDevice() {
  const float priority = 1.0f;
  auto queueInfo = makeInfo<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  auto info = makeInfo<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queueInfo;
  VkDevice device = VK_NULL_HANDLE;
  check(vkCreateDevice(physicalDevice_, &info, nullptr, &device), "vkCreateDevice");
  device_.reset(device);
  vkGetDeviceQueue(device, queueFamily_, 0, &queue_);

  auto poolInfo = makeInfo<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  poolInfo.queueFamilyIndex = queueFamily_;
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(device, &poolInfo, nullptr, &pool), "vkCreateCommandPool");
  commandPool_ = {device, pool};
}

std::uint32_t VulkanContext::memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                                        VkMemoryPropertyFlags preferred) const {
  const VkMemoryPropertyFlags ideal = required | preferred;
  std::optional<std::uint32_t> fallback;
  for (std::uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
    if (!(typeBits & (1u << i))) continue;
    const VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[i].propertyFlags;
    if ((flags & ideal) == ideal) return i;
    if ((flags & required) == required && !fallback) fallback = i;
  }
  if (!fallback)
    throw std::runtime_error("Vulkan: " + deviceName_ + " has no memory type with property flags " +
                             std::to_string(required) + " for this resource");
  return *fallback;
}

DeviceMemory VulkanContext::allocate(const VkMemoryRequirements& requirements,
                                     VkMemoryPropertyFlags required,
                                     VkMemoryPropertyFlags preferred) const {
  auto info = makeInfo<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = memoryType(requirements.memoryTypeBits, required, preferred);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  check(vkAllocateMemory(device(), &info, nullptr, &memory), "vkAllocateMemory");
  return {device(), memory};
}

Buffer VulkanContext::createBuffer(VkDeviceSize size, VkBufferUsageFlags usage,
                                   VkMemoryPropertyFlags required,
                                   VkMemoryPropertyFlags preferred) const {
  if (size == 0) throw std::runtime_error("Vulkan: cannot create a buffer of 0 bytes");
  // Every implementation has a host-visible coherent type, and coherent
  // memory spares the callers flushes and invalidations.
  const bool hostVisible = required & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
  if (hostVisible) required |= VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

  auto info = makeInfo<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer handle = VK_NULL_HANDLE;
  check(vkCreateBuffer(device(), &info, nullptr, &handle), "vkCreateBuffer");
  Buffer buffer;
  buffer.buffer_ = {device(), handle};
  buffer.size_ = size;

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device(), handle, &requirements);
  buffer.memory_ = allocate(requirements, required, preferred);
  check(vkBindBufferMemory(device(), handle, buffer.memory_.get(), 0), "vkBindBufferMemory");
  if (hostVisible)
    check(vkMapMemory(device(), buffer.memory_.get(), 0, VK_WHOLE_SIZE, 0, &buffer.mapped_),
          "vkMapMemory");
  return buffer;
}

Image2D VulkanContext::createImage(std::uint32_t width, std::uint32_t height, VkFormat format,
                                   VkImageUsageFlags usage, VkImageAspectFlags aspect) const {
  const std::uint32_t limit = properties_.limits.maxImageDimension2D;
  if (width == 0 || height == 0 || width > limit || height > limit)
    throw std::runtime_error("Vulkan: image size " + std::to_string(width) + "x" +
                             std::to_string(height) + " is outside 1.." + std::to_string(limit) +
                             " on " + deviceName_);

  auto info = makeInfo<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage handle = VK_NULL_HANDLE;
  check(vkCreateImage(device(), &info, nullptr, &handle), "vkCreateImage");
  Image2D image;
  image.image_ = {device(), handle};
  image.format_ = format;
  image.extent_ = {width, height};

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device(), handle, &requirements);
  image.memory_ = allocate(requirements, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  check(vkBindImageMemory(device(), handle, image.memory_.get(), 0), "vkBindImageMemory");

  auto viewInfo = makeInfo<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  viewInfo.image = handle;
  viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
  viewInfo.format = format;
  viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
  VkImageView view = VK_NULL_HANDLE;
  check(vkCreateImageView(device(), &viewInfo, nullptr, &view), "vkCreateImageView");
  image.view_ = {device(), view};
  return image;
}

ShaderModule VulkanContext::createShaderModule(std::span<const std::uint32_t> spirv) const {
  auto info = makeInfo<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  info.codeSize = spirv.size_bytes();
  info.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device(), &info, nullptr, &module), "vkCreateShaderModule");
  return {device(), module};
}

ComputeProgram VulkanContext::createComputeProgram(std::span<const std::uint32_t> spirv,
                                                   std::uint32_t storageBuffers,
                                                   std::uint32_t pushConstantBytes) const {
  ComputeProgram program;
  std::vector<VkDescriptorSetLayoutBinding> bindings(storageBuffers);
  for (std::uint32_t b = 0; b < storageBuffers; ++b)
    bindings[b] = {b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  auto setInfo = makeInfo<VkDescriptorSetLayoutCreateInfo>(
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  setInfo.bindingCount = storageBuffers;
  setInfo.pBindings = bindings.data();
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  check(vkCreateDescriptorSetLayout(device(), &setInfo, nullptr, &setLayout),
        "vkCreateDescriptorSetLayout");
  program.setLayout = {device(), setLayout};

  const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
  auto layoutInfo =
      makeInfo<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout;
  layoutInfo.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  check(vkCreatePipelineLayout(device(), &layoutInfo, nullptr, &layout), "vkCreatePipelineLayout");
  program.layout = {device(), layout};

  const ShaderModule shader = createShaderModule(spirv);
  auto info = makeInfo<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = makeInfo<VkPipelineShaderStageCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = shader.get();
  info.stage.pName = "main";
  info.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateComputePipelines(device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
        "vkCreateComputePipelines");
  program.pipeline = {device(), pipeline};
  return program;
}

Buffer VulkanContext::createHostStorageBuffer(std::size_t bytes) const {
  return createBuffer(VkDeviceSize(std::max<std::size_t>(bytes, 4)),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                      VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
}

BoundBuffers VulkanContext::bindStorageBuffers(const ComputeProgram& program,
                                               std::span<const VkBuffer> buffers) const {
  const auto count = std::uint32_t(buffers.size());
  const VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, count};
  auto poolInfo =
      makeInfo<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &poolSize;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  check(vkCreateDescriptorPool(device(), &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
  BoundBuffers bound;
  bound.pool = {device(), pool};
  const VkDescriptorSetLayout setLayout = program.setLayout.get();
  auto allocInfo =
      makeInfo<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  allocInfo.descriptorPool = pool;
  allocInfo.descriptorSetCount = 1;
  allocInfo.pSetLayouts = &setLayout;
  check(vkAllocateDescriptorSets(device(), &allocInfo, &bound.set), "vkAllocateDescriptorSets");
  std::vector<VkDescriptorBufferInfo> infos(count);
  std::vector<VkWriteDescriptorSet> writes(count);
  for (std::uint32_t b = 0; b < count; ++b) {
    infos[b] = {buffers[b], 0, VK_WHOLE_SIZE};
    writes[b] = makeInfo<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[b].dstSet = bound.set;
    writes[b].dstBinding = b;
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  vkUpdateDescriptorSets(device(), count, writes.data(), 0, nullptr);
  return bound;
}

void VulkanContext::submit(const std::function<void(VkCommandBuffer)>& record) {
  std::lock_guard lock(submitMutex_);
  auto allocInfo =
      makeInfo<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  allocInfo.commandPool = commandPool_.get();
  allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocInfo.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device(), &allocInfo, &commands), "vkAllocateCommandBuffers");
  auto release = [this](VkCommandBuffer buffer) {
    vkFreeCommandBuffers(device(), commandPool_.get(), 1, &buffer);
  };
  std::unique_ptr<VkCommandBuffer_T, decltype(release)> owner(commands, release);

  auto begin = makeInfo<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
  record(commands);
  check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");

  auto fenceInfo = makeInfo<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  VkFence fenceHandle = VK_NULL_HANDLE;
  check(vkCreateFence(device(), &fenceInfo, nullptr, &fenceHandle), "vkCreateFence");
  DeviceHandle<VkFence, vkDestroyFence> fence(device(), fenceHandle);

  auto submitInfo = makeInfo<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submitInfo.commandBufferCount = 1;
  submitInfo.pCommandBuffers = &commands;
  check(vkQueueSubmit(queue_, 1, &submitInfo, fenceHandle), "vkQueueSubmit");
  check(vkWaitForFences(device(), 1, &fenceHandle, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

}  // namespace geobrush::gpu
