// reuseFreedMemory: a large block freed and allocated again costs no new page faults.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstring>
#include <memory>

#include "geobrush/memory.hpp"

namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Allocates and touches `bytes`, then frees them; returns the page faults that took.
long faultsOfATouchedBlock(std::size_t bytes) {
  const long before = minorFaults();
  {
    auto block = std::make_unique<char[]>(bytes);
    std::memset(block.get(), 1, bytes);
  }
  return minorFaults() - before;
}

// AddressSanitizer replaces malloc with its own allocator, which ignores mallopt: there is no
// glibc heap to measure. gcc defines __SANITIZE_ADDRESS__; clang 14 only has __has_feature.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

}  // namespace

TEST(Memory, AFreedMeshSizedBlockIsReusedWithoutPageFaults) {
  if (kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's allocator is not glibc's";
  ASSERT_TRUE(geobrush::reuseFreedMemory());
  constexpr std::size_t kBytes = 16 << 20;  // a 168k-vertex mesh's halfedges
  faultsOfATouchedBlock(kBytes);
  // 4096 pages would fault in again if the block had gone back to the kernel.
  EXPECT_LT(faultsOfATouchedBlock(kBytes), 256);
}
