#include "render_thread.hpp"

namespace trainsim::camera {

RenderThread::RenderThread() : thread_([this] { loop(); }) {}

RenderThread::~RenderThread() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::shared_ptr<RenderThread> RenderThread::shared() {
  static std::mutex mutex;
  static std::weak_ptr<RenderThread> current;
  const std::lock_guard lock(mutex);
  std::shared_ptr<RenderThread> t = current.lock();
  if (!t) {
    t = std::make_shared<RenderThread>();
    current = t;
  }
  return t;
}

void RenderThread::loop() {
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      if (jobs_.empty())
        return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();
  }
}

}  // namespace trainsim::camera
