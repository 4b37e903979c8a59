// Data-parallel loops whose results do not depend on the number of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace geobrush {

namespace detail {
// This thread's flag for SerialOnThisThread. It lives in core, which a program links, rather than
// in every library that includes this header: a thread-local variable of a plugin, which is loaded
// and unloaded at run time, would be dynamic TLS.
bool& serialThread();
}  // namespace detail

// While one lives, parallelBlocks called on this thread with `threads` 0 runs on it alone: work
// done in the background leaves the other cores to the work waited for.
class SerialOnThisThread {
 public:
  SerialOnThisThread() : previous_(detail::serialThread()) { detail::serialThread() = true; }
  ~SerialOnThisThread() { detail::serialThread() = previous_; }
  SerialOnThisThread(const SerialOnThisThread&) = delete;
  SerialOnThisThread& operator=(const SerialOnThisThread&) = delete;

 private:
  bool previous_;
};

// Runs body(first, last) over fixed blocks of [0, count) on up to `threads` threads (0: one per
// hardware thread, or the calling thread alone under SerialOnThisThread). Callers compute each item
// from its own inputs alone, so the results are the same for any number of threads.
//
// With `progress`, the calling thread (one of the workers) calls progress(fraction of the blocks
// done) after each block it finishes, and progress(1) at the end; what progress throws (e.g. a
// cancellation) ends the loop and is rethrown.
template <typename Body>
void parallelBlocks(std::size_t count, std::size_t blockSize, int threads, const Body& body,
                    const std::function<void(double)>& progress = {}) {
  const std::size_t blocks = (count + blockSize - 1) / blockSize;
  const std::size_t wanted = threads > 0 ? std::size_t(threads)
                             : detail::serialThread()
                                 ? 1
                                 : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min(wanted, blocks);
  if (workers <= 1 && !progress) {
    body(std::size_t(0), count);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  double reported = 0;  // written by the calling thread only
  std::exception_ptr failure;
  std::mutex failureMutex;
  auto work = [&](bool caller) {
    try {
      for (std::size_t b = next++; b < blocks; b = next++) {
        body(b * blockSize, std::min(count, (b + 1) * blockSize));
        const std::size_t finished = ++done;
        if (caller && progress) progress(reported = double(finished) / double(blocks));
      }
    } catch (...) {
      const std::lock_guard lock(failureMutex);
      if (!failure) failure = std::current_exception();
      next = blocks;
    }
  };
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < workers; ++t)
      pool.emplace_back(work, false);
  } catch (const std::system_error&) {
    // Fewer threads do the same blocks.
  }
  work(true);
  for (auto& t : pool)
    t.join();
  if (failure) std::rethrow_exception(failure);
  // The other threads may have finished the last blocks.
  if (progress && reported < 1) progress(1.0);
}

}  // namespace geobrush
