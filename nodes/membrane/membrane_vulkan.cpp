// The membrane multigrid's level kernels on Vulkan (GeoBrush paper section 4.4, Eq. 4; the
// paper's appendix runs its iteration on the GPU too).
#include "membrane_vulkan.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "geobrush/gpu/vulkan_context.hpp"
// The generated header needs <cstdint> first.
#include "geobrush/shaders/membrane_level_comp.h"

namespace geobrush::membrane_detail {
namespace {

constexpr int kGroupSize = 64;  // local_size_x of the shader

enum Mode : std::int32_t { kApply = 0, kSubtract = 1, kChebyshev = 2 };
enum Shape : std::int32_t { kFull = 0, kPlate = 1, kLaplace = 2 };

Shape shapeOf(StencilShape shape) {
  switch (shape) {
    case StencilShape::Plate:
      return kPlate;
    case StencilShape::Laplace:
      return kLaplace;
    case StencilShape::Full:
      break;
  }
  return kFull;
}

// The shader's push constants, field for field.
struct Pass {
  std::int32_t begin, count, stride, mode, shape;
  std::int32_t b, x, d, outValues;
  std::int32_t mask, inverseDiagonal, regular, custom;
  float keep, gain;
};

// Where each vector lives in the vector buffer, in units of the level's padded size.
enum VectorSlot : int { kB, kX, kT, kD, kOut, kVectorSlots };

void computeBarrier(VkCommandBuffer commands, VkAccessFlags dstAccess,
                    VkPipelineStageFlags dstStage) {
  auto barrier = gpu::makeInfo<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, dstStage, 0, 1, &barrier, 0,
                       nullptr, 0, nullptr);
}

constexpr std::uint32_t kBindings = 3;  // vectors, coefficients, customOf

// The shader's pipeline and layouts: the same for every level, so made once per process (a
// pipeline takes lavapipe milliseconds to compile, and every dab makes a new hierarchy). Made
// after the Vulkan context, so destroyed before it at exit.
// The process's program, made on first use; context is the shared one. A failed creation throws
// and is retried on the next call.
const gpu::ComputeProgram& sharedProgram(gpu::VulkanContext& context) {
  static std::mutex mutex;
  static std::unique_ptr<gpu::ComputeProgram> program;
  const std::lock_guard lock(mutex);
  if (!program)
    program = std::make_unique<gpu::ComputeProgram>(
        context.createComputeProgram(membrane_level_comp, kBindings, sizeof(Pass)));
  return *program;
}

}  // namespace

struct VulkanLevelKernels::Resources {
  explicit Resources(gpu::VulkanContext& vulkan)
      : context(vulkan), program(sharedProgram(vulkan)) {}

  gpu::VulkanContext& context;
  const gpu::ComputeProgram& program;
  std::mutex mutex;  // held by every call: the vectors have one home on the device
  int size = 0;
  int begin = 0;  // the level's active range
  int count = 0;
  int stride = 0;
  Shape shape = kFull;
  int inverseDiagonalOffset = 0, regularOffset = 0, customOffset = 0;  // in `coefficients`
  gpu::Buffer vectors, coefficients, customOf;
  gpu::BoundBuffers bound;

  float* vector(VectorSlot slot) const {
    return static_cast<float*>(vectors.mapped()) + std::size_t(slot) * std::size_t(size);
  }

  void upload(VectorSlot slot, const float* values) const {
    std::memcpy(vector(slot) + begin, values + begin, std::size_t(count) * sizeof(float));
  }

  void download(VectorSlot slot, float* values) const {
    std::memcpy(values + begin, vector(slot) + begin, std::size_t(count) * sizeof(float));
  }

  Pass pass(Mode mode, VectorSlot x, VectorSlot out) const {
    Pass p{};
    p.begin = begin;
    p.count = count;
    p.stride = stride;
    p.mode = mode;
    p.shape = shape;
    p.b = kB * size;
    p.x = x * size;
    p.d = kD * size;
    p.outValues = out * size;
    p.mask = 0;
    p.inverseDiagonal = inverseDiagonalOffset;
    p.regular = regularOffset;
    p.custom = customOffset;
    return p;
  }

  void dispatch(VkCommandBuffer commands, const Pass& p) const {
    const VkPipelineLayout layout = program.layout.get();
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline.get());
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &bound.set, 0,
                            nullptr);
    vkCmdPushConstants(commands, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Pass), &p);
    vkCmdDispatch(commands, std::uint32_t((count + kGroupSize - 1) / kGroupSize), 1, 1);
  }

  void uploadCoefficients(const Level& level);
  void createDescriptorSet();

  // Runs the passes in one submission, a barrier after each.
  void run(std::span<const Pass> passes) const {
    if (count == 0) return;
    context.submit([&](VkCommandBuffer commands) {
      for (std::size_t k = 0; k < passes.size(); ++k) {
        dispatch(commands, passes[k]);
        if (k + 1 < passes.size())
          computeBarrier(commands, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
      }
      computeBarrier(commands, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
    });
  }
};

void VulkanLevelKernels::Resources::uploadCoefficients(const Level& level) {
  Resources& r = *this;
  const SingleCoefficients& single = level.single;
  r.inverseDiagonalOffset = r.size;
  r.regularOffset = 2 * r.size;
  r.customOffset = r.regularOffset + kSlots;
  const std::size_t floats = std::size_t(r.customOffset) + single.custom.size() * kSlots;
  r.coefficients = r.context.createHostStorageBuffer(floats * sizeof(float));
  float* out = static_cast<float*>(r.coefficients.mapped());
  std::memcpy(out, single.mask.data(), std::size_t(r.size) * sizeof(float));
  std::memcpy(out + r.inverseDiagonalOffset, single.inverseDiagonal.data(),
              std::size_t(r.size) * sizeof(float));
  std::memcpy(out + r.regularOffset, single.regular.data(), kSlots * sizeof(float));
  for (std::size_t c = 0; c < single.custom.size(); ++c)
    std::memcpy(out + r.customOffset + c * kSlots, single.custom[c].data(), kSlots * sizeof(float));

  r.customOf = r.context.createHostStorageBuffer(std::size_t(r.size) * sizeof(std::int32_t));
  std::memcpy(r.customOf.mapped(), level.customOfNode.data(),
              std::size_t(r.size) * sizeof(std::int32_t));
  r.vectors = r.context.createHostStorageBuffer(std::size_t(kVectorSlots) * std::size_t(r.size) *
                                                sizeof(float));
  std::memset(r.vectors.mapped(), 0, r.vectors.size());
}

void VulkanLevelKernels::Resources::createDescriptorSet() {
  const std::array<VkBuffer, kBindings> buffers = {vectors.handle(), coefficients.handle(),
                                                   customOf.handle()};
  bound = context.bindStorageBuffers(program, buffers);
}

bool VulkanLevelKernels::available() {
  return gpu::VulkanContext::shared() != nullptr;
}

VulkanLevelKernels::VulkanLevelKernels(const Level& level) {
  gpu::VulkanContext* context = gpu::VulkanContext::shared();
  if (context == nullptr) {
    std::string message = "membrane: no Vulkan device: ";
    message += gpu::VulkanContext::unavailableReason();
    throw std::runtime_error(message);
  }
  resources_ = std::make_unique<Resources>(*context);
  Resources& r = *resources_;
  r.size = int(level.grid.size());
  r.begin = level.activeBegin;
  r.count = level.activeEnd - level.activeBegin;
  r.stride = level.grid.stride();
  r.shape = shapeOf(level.shape);
  r.uploadCoefficients(level);
  r.createDescriptorSet();
}

VulkanLevelKernels::~VulkanLevelKernels() = default;

void VulkanLevelKernels::apply(const float* x, float* out) {
  Resources& r = *resources_;
  const std::lock_guard lock(r.mutex);
  r.upload(kX, x);
  const Pass pass = r.pass(kApply, kX, kOut);
  r.run({&pass, 1});
  r.download(kOut, out);
}

void VulkanLevelKernels::subtract(const float* b, const float* x, float* out) {
  Resources& r = *resources_;
  const std::lock_guard lock(r.mutex);
  r.upload(kB, b);
  r.upload(kX, x);
  const Pass pass = r.pass(kSubtract, kX, kOut);
  r.run({&pass, 1});
  r.download(kOut, out);
}

void VulkanLevelKernels::chebyshev(const float* b, float* x, float* d,
                                   std::span<const ChebyshevStep> steps) {
  Resources& r = *resources_;
  const std::lock_guard lock(r.mutex);
  r.upload(kB, b);
  r.upload(kX, x);
  r.upload(kD, d);
  std::vector<Pass> passes;
  VectorSlot current = kX, next = kT;
  for (const ChebyshevStep& step : steps) {
    Pass pass = r.pass(kChebyshev, current, next);
    pass.keep = step.keep;
    pass.gain = step.gain;
    passes.push_back(pass);
    std::swap(current, next);
  }
  r.run(passes);
  r.download(current, x);
  r.download(kD, d);
}

VulkanCycleKernels::VulkanCycleKernels(const MembraneHierarchy& hierarchy) {
  const auto& levels = hierarchy.levels();
  for (std::size_t l = 0; l + 1 < levels.size(); ++l)
    levels_.push_back(std::make_unique<VulkanLevelKernels>(levels[l]));
}

}  // namespace geobrush::membrane_detail

namespace geobrush {

membrane_detail::VulkanCycleKernels& MembraneHierarchy::vulkanKernels() const {
  const std::lock_guard lock(vulkan_->mutex);
  if (!vulkan_->kernels)
    vulkan_->kernels = std::make_shared<membrane_detail::VulkanCycleKernels>(*this);
  return *vulkan_->kernels;
}

MembraneVulkanDevice membraneVulkanDevice() {
  MembraneVulkanDevice device;
  const gpu::VulkanContext* context = gpu::VulkanContext::shared();
  if (context == nullptr) {
    device.unavailableReason = gpu::VulkanContext::unavailableReason();
    return device;
  }
  device.available = true;
  device.name = context->deviceName();
  return device;
}

const char* membraneKernelName(MembraneKernel kernel) {
  return kernel == MembraneKernel::Vulkan ? "vulkan" : "cpu";
}

}  // namespace geobrush
