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

}  // namespace

TEST(Memory, AFreedMeshSizedBlockIsReusedWithoutPageFaults) {
  ASSERT_TRUE(geobrush::reuseFreedMemory());
  constexpr std::size_t kBytes = 16 << 20;  // a 168k-vertex mesh's halfedges
  faultsOfATouchedBlock(kBytes);
  // 4096 pages would fault in again if the block had gone back to the kernel.
  EXPECT_LT(faultsOfATouchedBlock(kBytes), 256);
}
