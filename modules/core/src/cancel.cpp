#include "trainsim/core/cancel.hpp"

#include <string>

#include "trainsim/core/error.hpp"

namespace trainsim {
namespace {
thread_local const std::atomic<bool>* t_flag = nullptr;
}  // namespace

CancelScope::CancelScope(const std::atomic<bool>* flag) : previous_(t_flag) {
  t_flag = flag;
}

CancelScope::~CancelScope() {
  t_flag = previous_;
}

void throwIfCancelled(std::string_view what) {
  if (t_flag != nullptr && t_flag->load(std::memory_order_relaxed))
    throw Cancelled(std::string(what) + " cancelled");
}

}  // namespace trainsim
