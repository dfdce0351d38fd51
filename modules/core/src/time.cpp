#include "trainsim/core/time.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "trainsim/core/error.hpp"

namespace trainsim {

TimeNs fromSeconds(double seconds) {
  const double ns = std::round(seconds * 1e9);
  // 2^63 is exactly representable as a double; anything at or above it overflows int64.
  constexpr double kLimit = 9223372036854775808.0;
  if (!std::isfinite(ns) || ns >= kLimit || ns < -kLimit) {
    throw ConfigError("time " + std::to_string(seconds) + " s does not fit in int64 nanoseconds");
  }
  return static_cast<TimeNs>(ns);
}

}  // namespace trainsim
