#include "ring_order.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include <emmintrin.h>

namespace trainsim::lidar::detail {
namespace {

// Copies a point as two 16-byte moves (copied as a LidarPoint, it went field by field).
void copyPoint(const LidarPoint& from, LidarPoint& to) {
  const auto* f = reinterpret_cast<const __m128i*>(&from);
  auto* t = reinterpret_cast<__m128i*>(&to);
  _mm_store_si128(t, _mm_load_si128(f));
  _mm_store_si128(t + 1, _mm_load_si128(f + 1));
}

}  // namespace

std::size_t orderRing(const float* keys, const LidarPoint* from, std::size_t columns,
                      std::size_t returns, std::vector<std::uint64_t>& order,
                      std::vector<std::uint32_t>& start, LidarPoint* to) {
  const std::size_t slots = columns * returns;
  std::fill(start.begin(), start.end(), 0u);
  const auto scale = static_cast<float>(columns) / 4.0f;
  const auto bucket = [&](float key) {
    return std::min(columns - 1, static_cast<std::size_t>(key * scale));
  };
  std::size_t n = 0;
  for (std::size_t s = 0; s < slots; ++s)
    if (keys[s] >= 0.0f) {
      ++start[bucket(keys[s]) + 1];
      ++n;
    }
  for (std::size_t b = 0; b < columns; ++b)
    start[b + 1] += start[b];
  order.resize(n);
  // Filled from the last slot back: a ring's azimuth falls column by column, so each bucket
  // then fills in rising order, the points go out nearly in sequence, and the insertion sort
  // has next to nothing to do.
  for (std::size_t s = slots; s-- > 0;) {
    // The points come from the other core's writes or the shared cache, not this core's, and
    // go to an output the raw traversal has pushed out of it: ask for them well ahead (2 kB
    // back for the reads, 1 kB on for the writes; 16 points back, the old distance, left the
    // loop waiting on its loads, and 0.01–0.02 of the frame with it).
    if (s >= 64)
      __builtin_prefetch(from + s - 64);
    if (keys[s] >= 0.0f) {
      const std::uint32_t at = start[bucket(keys[s])]++;
      if (at + 32 < n)
        __builtin_prefetch(to + at + 32, 1);
      order[at] = static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(keys[s])) << 32 | s;
      copyPoint(from[s], to[at]);
    }
  }
  for (std::size_t i = 1; i < n; ++i)
    for (std::size_t j = i; j > 0 && order[j] < order[j - 1]; --j) {
      std::swap(order[j], order[j - 1]);
      std::swap(to[j], to[j - 1]);
    }
  return n;
}

}  // namespace trainsim::lidar::detail
