// The heavy kernels of the membrane's multigrid (GeoBrush paper section 4.4, Eq. 4) as Vulkan
// compute passes (shaders/membrane_level.comp): the operator of one level, its residual and the
// Chebyshev smoother's steps, in single precision as the CPU cycle runs them.
//
// On Mesa's lavapipe (the CPU device) a dispatch with its barrier costs about 50 us and a pass
// runs slower than the vectorized CPU kernel, so the solver itself stays on the CPU there; these
// kernels are what a GPU cycle would run, and the tests hold them to the CPU kernels.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "membrane_levels.hpp"

namespace geobrush::membrane_detail {

// One Chebyshev step's coefficients (see chebyshevStep).
struct ChebyshevStep {
  float keep;
  float gain;
};

// A level's coefficients uploaded once; every call uploads its input vectors, runs in one
// submission and reads its outputs back. Vectors are padded arrays of the level's size. Needs a
// Vulkan device: check available() first; the constructor throws std::runtime_error without one.
// Not thread-safe: one caller at a time per object.
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

}  // namespace geobrush::membrane_detail
