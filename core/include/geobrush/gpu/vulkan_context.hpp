// The process-wide Vulkan device (no window, no surface) that the renderer
// and compute kernels share. Code that includes this header needs the Vulkan
// headers (link Vulkan::Vulkan).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace geobrush::gpu {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" and the like.
std::string_view toString(VkResult result);
// Throws std::runtime_error("Vulkan: <call> failed: <result>") unless VK_SUCCESS.
void check(VkResult result, std::string_view call);

// A zeroed Vulkan structure with its sType set: `auto info =
// makeInfo<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);`.
template <typename T>
T makeInfo(VkStructureType type) {
  T info{};
  info.sType = type;
  return info;
}

// A Vulkan object destroyed with the device that made it when it goes out of scope.
template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class DeviceHandle {
 public:
  DeviceHandle() = default;
  DeviceHandle(VkDevice device, T handle) : device_(device), handle_(handle) {}
  DeviceHandle(DeviceHandle&& other) noexcept
      : device_(other.device_), handle_(std::exchange(other.handle_, VK_NULL_HANDLE)) {}
  DeviceHandle& operator=(DeviceHandle&& other) noexcept {
    if (this != &other) {
      reset();
      device_ = other.device_;
      handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
    }
    return *this;
  }
  DeviceHandle(const DeviceHandle&) = delete;
  DeviceHandle& operator=(const DeviceHandle&) = delete;
  ~DeviceHandle() { reset(); }

  T get() const { return handle_; }
  void reset() {
    if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
    handle_ = VK_NULL_HANDLE;
  }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  T handle_ = VK_NULL_HANDLE;
};

using DeviceMemory = DeviceHandle<VkDeviceMemory, vkFreeMemory>;
using ShaderModule = DeviceHandle<VkShaderModule, vkDestroyShaderModule>;
using PipelineLayout = DeviceHandle<VkPipelineLayout, vkDestroyPipelineLayout>;
using Pipeline = DeviceHandle<VkPipeline, vkDestroyPipeline>;
using RenderPass = DeviceHandle<VkRenderPass, vkDestroyRenderPass>;
using Framebuffer = DeviceHandle<VkFramebuffer, vkDestroyFramebuffer>;
using ImageView = DeviceHandle<VkImageView, vkDestroyImageView>;
using DescriptorSetLayout = DeviceHandle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = DeviceHandle<VkDescriptorPool, vkDestroyDescriptorPool>;

// A compute kernel ready to dispatch: storage buffers at bindings 0, 1, ... of descriptor set 0,
// push constants from offset 0, the compute stage of its SPIR-V's `main`.
struct ComputeProgram {
  DescriptorSetLayout setLayout;
  PipelineLayout layout;
  Pipeline pipeline;
};

// A descriptor set binding buffers to a compute program's storage-buffer bindings, and the pool
// it is freed with.
struct BoundBuffers {
  DescriptorPool pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};

// A buffer with memory of its own. Host-visible buffers are also host-coherent
// and stay mapped for their whole life, so they need no flushes.
class Buffer {
 public:
  VkBuffer handle() const { return buffer_.get(); }
  VkDeviceSize size() const { return size_; }
  // The mapped memory of a host-visible buffer, else null.
  void* mapped() const { return mapped_; }

 private:
  friend class VulkanContext;
  DeviceMemory memory_;  // declared first: freed after the buffer is destroyed
  DeviceHandle<VkBuffer, vkDestroyBuffer> buffer_;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

// A 2D image (one mip level, one layer) in device-local memory where the
// device has it, with a view.
class Image2D {
 public:
  VkImage handle() const { return image_.get(); }
  VkImageView view() const { return view_.get(); }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }

 private:
  friend class VulkanContext;
  DeviceMemory memory_;
  DeviceHandle<VkImage, vkDestroyImage> image_;
  ImageView view_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
};

// What device selection needs to know about one physical device.
struct DeviceInfo {
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  // Vulkan 1.2 or later with a queue family that does graphics and compute.
  bool usable = false;
};

// Index into `devices` (in enumeration order, as `vulkaninfo` numbers them)
// of the device to use. `forced` (the value of GEOBRUSH_VK_DEVICE) picks one
// by index or by a case-insensitive substring of its name; when empty, the
// first usable discrete GPU wins, then integrated, virtual, CPU, other.
// Throws std::runtime_error listing the devices when nothing fits.
std::size_t pickDevice(std::span<const DeviceInfo> devices, std::string_view forced);

// One Vulkan 1.2 instance and device with a single graphics+compute queue.
// Every call is thread-safe; submissions are serialized on the one queue.
class VulkanContext {
 public:
  // The shared context, created on first use; null when no usable device
  // exists (see unavailableReason()). Destroyed at process exit.
  static VulkanContext* shared();
  // Why shared() is null; empty when it is not.
  static const std::string& unavailableReason();

  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;
  ~VulkanContext();

  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_.get(); }
  std::uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const std::string& deviceName() const { return deviceName_; }

  // Index of a memory type allowed by `typeBits` with all `required` flags,
  // having the `preferred` ones too where possible. Throws when none fits.
  std::uint32_t memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                           VkMemoryPropertyFlags preferred = 0) const;

  Buffer createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags required,
                      VkMemoryPropertyFlags preferred = 0) const;
  Image2D createImage(std::uint32_t width, std::uint32_t height, VkFormat format,
                      VkImageUsageFlags usage, VkImageAspectFlags aspect) const;
  ShaderModule createShaderModule(std::span<const std::uint32_t> spirv) const;
  // The program of a compute shader reading `storageBuffers` storage buffers and
  // `pushConstantBytes` bytes of push constants.
  ComputeProgram createComputeProgram(std::span<const std::uint32_t> spirv,
                                      std::uint32_t storageBuffers,
                                      std::uint32_t pushConstantBytes) const;
  // A host-visible, host-coherent storage buffer of `bytes` (at least 4), mapped for its life;
  // host-cached where the device has such memory, since the host reads results back from it and
  // reads from uncached (write-combined) memory crawl on a discrete GPU.
  Buffer createHostStorageBuffer(std::size_t bytes) const;
  // `buffers` bound, in order, to bindings 0, 1, ... of `program`'s storage buffers.
  BoundBuffers bindStorageBuffers(const ComputeProgram& program,
                                  std::span<const VkBuffer> buffers) const;

  // Records a primary command buffer with `record`, submits it and waits for
  // it on a fence.
  void submit(const std::function<void(VkCommandBuffer)>& record);

  // An object made once per context by `make()` (returning std::unique_ptr<T>),
  // e.g. a pipeline, kept until the context is destroyed. T's destructor
  // must still be loaded then, so plugins that unload must not cache here.
  template <typename T, typename Make>
  T& cached(const std::string& key, Make&& make) {
    std::lock_guard lock(cacheMutex_);
    auto& slot = cache_[key];
    if (!slot) slot = std::shared_ptr<void>(std::forward<Make>(make)());
    return *static_cast<T*>(slot.get());
  }

 private:
  struct InstanceDeleter {
    void operator()(VkInstance instance) const { vkDestroyInstance(instance, nullptr); }
  };
  struct DeviceDeleter {
    void operator()(VkDevice device) const { vkDestroyDevice(device, nullptr); }
  };

  VulkanContext();
  DeviceMemory allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required,
                        VkMemoryPropertyFlags preferred) const;
  void createInstance();
  void choosePhysicalDevice();
  void createDevice();

  std::unique_ptr<VkInstance_T, InstanceDeleter> instance_;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memoryProperties_{};
  std::string deviceName_;
  std::uint32_t queueFamily_ = 0;
  std::unique_ptr<VkDevice_T, DeviceDeleter> device_;
  VkQueue queue_ = VK_NULL_HANDLE;
  DeviceHandle<VkCommandPool, vkDestroyCommandPool> commandPool_;
  std::mutex submitMutex_;  // guards queue_ and commandPool_
  std::mutex cacheMutex_;
  std::map<std::string, std::shared_ptr<void>, std::less<>> cache_;
};

}  // namespace geobrush::gpu
