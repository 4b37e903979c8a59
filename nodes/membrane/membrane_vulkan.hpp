// The heavy kernels of the membrane's multigrid (GeoBrush paper section 4.4, Eq. 4) as Vulkan
// compute passes (shaders/membrane_level.comp): the operator of one level, its residual and the
// Chebyshev smoother's steps, in single precision as the CPU cycle runs them. With
// MembraneKernel::Vulkan the cycle runs the smoother and residual of the finest level, and of the
// coarse levels with at least MembraneOptions::vulkanMinUnknowns unknowns, through them; the band
// sweeps and the coarsest solve stay on the CPU (see membrane.hpp), so each kernel is one
// submission with its uploads and readback. Restriction and prolongation stay there too: the band
// sweeps beside them need the vectors on the host, so device transfers would save no round trip.
//
// On Mesa's lavapipe (the CPU device) a dispatch with its barrier costs about 50 us on an idle
// machine (milliseconds when its threads compete with other work) and a pass runs slower than
// the vectorized CPU kernel; on a discrete GPU each submission's round trip costs more than the
// CPU's pass. So the node's kernel=auto runs the CPU kernel, and these passes are opt-in.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "membrane.hpp"
#include "membrane_levels.hpp"

namespace geobrush {

// The device that MembraneKernel::Vulkan runs on: the shared Vulkan context's (the first discrete
// GPU, else integrated, ..., else lavapipe; GEOBRUSH_VK_DEVICE forces one).
struct MembraneVulkanDevice {
  bool available = false;         // a usable Vulkan device exists
  std::string name;               // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"; empty without one
  std::string unavailableReason;  // why there is none; empty when there is one
};

MembraneVulkanDevice membraneVulkanDevice();

// "cpu" or "vulkan".
const char* membraneKernelName(MembraneKernel kernel);

}  // namespace geobrush

namespace geobrush::membrane_detail {

// One Chebyshev step's coefficients (see chebyshevStep).
struct ChebyshevStep {
  float keep;
  float gain;
};

// A level's coefficients uploaded once; every call uploads its input vectors, runs in one
// submission and reads its outputs back. Vectors are padded arrays of the level's size. Needs a
// Vulkan device: check available() first; the constructor throws std::runtime_error without one.
// Thread-safe: calls on one object take turns (its vectors live in one device buffer).
class VulkanLevelKernels {
 public:
  static bool available();

  explicit VulkanLevelKernels(const Level& level);
  ~VulkanLevelKernels();
  VulkanLevelKernels(const VulkanLevelKernels&) = delete;
  VulkanLevelKernels& operator=(const VulkanLevelKernels&) = delete;

  // out = A x.
  void apply(const float* x, float* out);
  // out = b - A x.
  void subtract(const float* b, const float* x, float* out);
  // The steps in order, as chebyshevStep runs them from x and d, one dispatch each with a barrier
  // between them, in one submission; x and d are updated in place.
  void chebyshev(const float* b, float* x, float* d, std::span<const ChebyshevStep> steps);

 private:
  struct Resources;
  std::unique_ptr<Resources> resources_;
};

// The kernels of the levels that a hierarchy's cycle smooths: all but the coarsest.
class VulkanCycleKernels {
 public:
  explicit VulkanCycleKernels(const MembraneHierarchy& hierarchy);
  // Level `index` of the hierarchy, index + 1 < its level count.
  VulkanLevelKernels& level(std::size_t index) const { return *levels_[index]; }

 private:
  std::vector<std::unique_ptr<VulkanLevelKernels>> levels_;
};

}  // namespace geobrush::membrane_detail
