#pragma once

#include <atomic>
#include <string_view>

namespace trainsim {

/// Cooperative cancellation for long work that takes no cancel parameter of its own (the plan
/// stages, deep in track geometry and the plan writers). A CancelScope installs a flag for the
/// calling thread; throwIfCancelled() polls it and throws Cancelled (exit 1) once it is set.
/// Scopes nest; the innermost one counts. Polling costs one thread-local read and one relaxed
/// load, so loops may poll every few hundred iterations.
class CancelScope {
 public:
  explicit CancelScope(const std::atomic<bool>* flag);
  ~CancelScope();
  CancelScope(const CancelScope&) = delete;
  CancelScope& operator=(const CancelScope&) = delete;

 private:
  const std::atomic<bool>* previous_;
};

/// Throws Cancelled("<what> cancelled") if the calling thread's scope flag is set.
void throwIfCancelled(std::string_view what = "plan");

}  // namespace trainsim
