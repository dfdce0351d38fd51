#pragma once
// Private to the camera module: the one thread every VTK call of the process runs on.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

namespace trainsim::camera {

// An OpenGL context belongs to one thread at a time, and Xlib is not thread-safe without
// XInitThreads, which would have to run before anything else opens a display. So every VTK call
// of every renderer runs on one thread of the process; the software rasteriser (llvmpipe)
// spreads each draw over the cores itself.
class RenderThread {
 public:
  RenderThread();
  ~RenderThread();
  RenderThread(const RenderThread&) = delete;
  RenderThread& operator=(const RenderThread&) = delete;

  // Runs f on the render thread and returns its result (or rethrows its exception).
  template <typename F>
  auto run(F f) -> decltype(f()) {
    std::packaged_task<decltype(f())()> task(std::move(f));
    auto result = task.get_future();
    {
      const std::lock_guard lock(mutex_);
      jobs_.emplace_back([&task] { task(); });
    }
    wake_.notify_one();
    return result.get();
  }

  // The process's render thread, made when the first renderer needs it, ended with the last.
  static std::shared_ptr<RenderThread> shared();

 private:
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stop_ = false;
  std::thread thread_;  // last: starts after the members it uses
};

}  // namespace trainsim::camera
