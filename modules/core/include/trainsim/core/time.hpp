#pragma once

#include <cstdint>

namespace trainsim {

/// Simulation time: integer nanoseconds since the start of the run. Never accumulate float
/// seconds; convert with toSeconds() at the edges only.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;

/// Seconds as a double (exact for |t| < 2^53 ns, about 104 days).
constexpr double toSeconds(TimeNs t) {
  return static_cast<double>(t) * 1e-9;
}

/// Nearest whole nanosecond to `seconds`. Throws ConfigError if it is not finite or does not
/// fit in TimeNs.
TimeNs fromSeconds(double seconds);

/// True when `period` is a positive whole multiple of `base` (base > 0).
constexpr bool isMultipleOf(TimeNs period, TimeNs base) {
  return base > 0 && period > 0 && period % base == 0;
}

}  // namespace trainsim
