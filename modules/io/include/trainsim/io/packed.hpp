#pragma once
// Packed little-endian records (the LiDAR's point_info and PCD data): a value's bytes at `out`,
// which then moves past them. The project builds for x86-64, which is little-endian.
#include <cstring>

namespace trainsim::io {

template <typename T>
void putPacked(char*& out, T value) {
  std::memcpy(out, &value, sizeof value);
  out += sizeof value;
}

}  // namespace trainsim::io
