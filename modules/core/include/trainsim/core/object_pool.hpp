#pragma once
// Objects kept for reuse by whoever needs one next: buffers of a few MB that a hot loop would
// otherwise allocate and initialise every time. Thread-safe; holds as many objects as were ever
// in use at once.
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace trainsim {

template <typename T>
class ObjectPool {
 public:
  /// A free object, or make() when there is none.
  template <typename Make>
  std::unique_ptr<T> take(Make&& make) {
    {
      const std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<T> item = std::move(free_.back());
        free_.pop_back();
        return item;
      }
    }
    return std::forward<Make>(make)();
  }
  std::unique_ptr<T> take() {
    return take([] { return std::make_unique<T>(); });
  }
  /// Hands `item` back for the next take().
  void give(std::unique_ptr<T> item) {
    const std::lock_guard lock(mutex_);
    free_.push_back(std::move(item));
  }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace trainsim
