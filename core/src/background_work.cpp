#include "background_work.hpp"

#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace geobrush {

namespace {

class BackgroundWork {
 public:
  ~BackgroundWork() {
    std::unique_lock lock(mutex_);
    next_ = nullptr;
    lock.unlock();
    if (thread_.joinable()) thread_.join();
  }

  void post(std::function<void()> work) {
    std::lock_guard lock(mutex_);
    next_ = std::move(work);
    if (running_) return;
    if (thread_.joinable()) thread_.join();  // done with its last piece: it is leaving
    try {
      thread_ = std::thread([this] { runPosted(); });
      running_ = true;
    } catch (const std::system_error&) {
      next_ = nullptr;
    }
  }

 private:
  void runPosted() {
    for (;;) {
      std::function<void()> work;
      {
        std::lock_guard lock(mutex_);
        if (!next_) {
          running_ = false;
          return;
        }
        work = std::exchange(next_, nullptr);
      }
      work();
    }
  }

  std::mutex mutex_;
  std::thread thread_;
  bool running_ = false;
  std::function<void()> next_;
};

// Made as the library loads, before any object of a program's that may post work, and so
// destroyed after them all.
BackgroundWork backgroundWork;

}  // namespace

void postBackgroundWork(std::function<void()> work) {
  backgroundWork.post(std::move(work));
}

}  // namespace geobrush
