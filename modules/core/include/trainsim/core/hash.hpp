#pragma once

#include <cstdint>
#include <string_view>

namespace trainsim {

/// FNV-1a, 64 bit: a fast, stable, non-cryptographic hash of bytes. Used for stream ids and
/// scenario fingerprints, where stability across builds and platforms is what matters.
constexpr std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // offset basis
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;  // prime
  }
  return h;
}

}  // namespace trainsim
