#pragma once
// A packet's returns worked out eight lanes at a time in vector registers (SSE2, the x86-64
// baseline, or AVX2 where the processor has it; the same bytes either way): incidence,
// Lambertian-Beckmann backscatter, range noise, deskewing, intensity, the ring's azimuth key and
// the points, for one ray a pulse.
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <emmintrin.h>

#include <Eigen/Core>

#include "trainsim/lidar/intensity.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"

namespace trainsim::lidar::detail {

// A monotonic stand-in for the azimuth atan2(y, x) mapped to [0, 2π): 0 on +x, rising
// counter-clockwise to 4 just before it (the "diamond angle"). It orders points as the azimuth
// does, with one division instead of an atan2 (in float: points less than about 1e-7 rad apart
// may tie or swap, which nothing downstream can tell). y = −0 counts as on +x, as the quadrant
// rule (y ≥ 0) counts it. Never negative (−0 comes out as +0), so the float's bits order as the
// value does.
inline float pseudoAzimuth(float x, float y) {
  const float d = std::abs(x) + std::abs(y);
  if (d == 0.0f)
    return 0.0f;
  const float r = y / d;
  const float a = x >= 0.0f ? r : 2.0f - r;
  return (a < 0.0f ? a + 4.0f : a) + 0.0f;
}

/// A point's place in its ring: its pseudoAzimuth() from the front (`sign` 1, KITTI's order for a
/// whole revolution) or from the rear (−1: a scan within an azimuth window centred forward then
/// runs unbroken from the window's right edge to its left). Negating is exact: the keys of a
/// whole revolution are the same bits either way this is written.
inline float ringKey(float x, float y, float sign) {
  return pseudoAzimuth(sign * x, sign * y);
}

/// Writes a point with two 16-byte stores rather than a store per field.
inline void storePoint(LidarPoint& to, const Eigen::Vector3f& xyz, float intensity, float range_m,
                       std::uint32_t object, std::uint16_t column, std::uint16_t ring,
                       scene::ClassId cls, std::uint8_t material, std::uint8_t return_index) {
  static_assert(offsetof(LidarPoint, xyz) == 0 && offsetof(LidarPoint, intensity) == 12 &&
                offsetof(LidarPoint, range_m) == 16 && offsetof(LidarPoint, object) == 20 &&
                offsetof(LidarPoint, column) == 24 && offsetof(LidarPoint, ring) == 26 &&
                offsetof(LidarPoint, cls) == 28 && offsetof(LidarPoint, material) == 30 &&
                offsetof(LidarPoint, return_index) == 31 && sizeof(scene::ClassId) == 2);
  auto* out = reinterpret_cast<__m128i*>(&to);
  _mm_store_si128(out, _mm_castps_si128(_mm_setr_ps(xyz.x(), xyz.y(), xyz.z(), intensity)));
  _mm_store_si128(out + 1,
                  _mm_setr_epi32(std::bit_cast<int>(range_m), static_cast<int>(object),
                                 static_cast<int>(column | static_cast<std::uint32_t>(ring) << 16),
                                 static_cast<int>(cls | static_cast<std::uint32_t>(material) << 16 |
                                                  static_cast<std::uint32_t>(return_index) << 24)));
}

/// A slot's key when it holds no return.
inline constexpr float kNoReturn = -1.0f;

/// What a task's packets share: the scanner's settings and the laser's tables.
struct PacketSetup {
  const Backscatter* backscatter = nullptr;  // by material id
  double sigma0 = 0.0, sigma1 = 0.0;         // range noise: σ = sigma0 + sigma1 · range
  double threshold = 0.0;                    // the least reflectivity that returns
  double detectable = 0.0;                   // the least reflectivity / range² (LidarParams)
  float range_min = 0.0f, range_max = 0.0f;
  bool falloff = false;
  IntensityScale scale = IntensityScale::kUnit;
  /// The columns' deskewing, field f of column c at frames[f · padded + c] (the scanner's
  /// Scratch::frames: rotation row-major from field `deskew`, translation from `shift`).
  const float* frames = nullptr;
  std::size_t padded = 0, deskew = 0, shift = 0;
  const float *ax = nullptr, *ay = nullptr, *az = nullptr;  // the laser's beam axes by column
  /// Where the laser's beam leaves the head, by column (Scanner::origin()); null: at the origin.
  const float *bx = nullptr, *by = nullptr, *bz = nullptr;
  /// The laser's directions by column, to key points by their coordinates as measured
  /// (LidarParams::motion_compensated off); null: keyed by the deskewed ones. `origins` the
  /// same for the beams' origins (null: at the origin).
  const Eigen::Vector3d* directions = nullptr;
  const Eigen::Vector3d* origins = nullptr;
  float key_sign = 1.0f;  // ringKey()'s: −1 keys from the rear
  std::uint16_t ring = 0;
  std::size_t returns = 1;  // slots a pulse has
};

/// Which build of the returns to run: the best the processor has, or one named (for tests that
/// compare them; kAvx2 only where avx2Returns()).
enum class Isa { kBest, kSse2, kAvx2 };

/// Whether the processor runs the AVX2 build of the returns (both give the same bytes).
bool avx2Returns();

/// Works out the returns of columns c0 + k, k < lanes ≤ 8, from their cast `packet`, with
/// noise[k · returns] and kept[k] their draws (kept 0: dropped): writes the first slot of each
/// (slot (c0 + k) · returns of `points` and `keys`; the key kNoReturn where it has no return,
/// and then its point is not to be read) and returns how many returned.
std::size_t packetReturns(const PacketSetup& setup, const RayPacket& packet, std::size_t c0,
                          std::size_t lanes, const double* noise, const std::uint8_t* kept,
                          LidarPoint* points, float* keys, Isa isa = Isa::kBest);

}  // namespace trainsim::lidar::detail
