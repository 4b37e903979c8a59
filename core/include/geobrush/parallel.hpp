// Data-parallel loops whose results do not depend on the number of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace geobrush {

// Runs body(first, last) over fixed blocks of [0, count) on up to `threads` threads (0: one per
// hardware thread). Callers compute each item from its own inputs alone, so the results are the
// same for any number of threads.
template <typename Body>
void parallelBlocks(std::size_t count, std::size_t blockSize, int threads, const Body& body) {
  const std::size_t blocks = (count + blockSize - 1) / blockSize;
  const std::size_t wanted =
      threads > 0 ? std::size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min(wanted, blocks);
  if (workers <= 1) {
    body(std::size_t(0), count);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  auto work = [&] {
    try {
      for (std::size_t b = next++; b < blocks; b = next++)
        body(b * blockSize, std::min(count, (b + 1) * blockSize));
    } catch (...) {
      const std::lock_guard lock(failureMutex);
      if (!failure) failure = std::current_exception();
      next = blocks;
    }
  };
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < workers; ++t)
      pool.emplace_back(work);
  } catch (const std::system_error&) {
    // Fewer threads do the same blocks.
  }
  work();
  for (auto& t : pool)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace geobrush
