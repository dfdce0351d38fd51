// A packet's returns in vector registers: the kernel (packet_returns_kernel.inc) compiled twice,
// for SSE2 (the x86-64 baseline) and for AVX2, and the AVX2 one run where the processor has it.
// Written with GCC's vector types (arithmetic and comparisons lane by lane) because the compiler
// does not vectorise this loop by itself (its conversions between float and double and its square
// root stop it) and Eigen 3.4 converts float to double one lane at a time. The AVX2 build is
// compiled by a target pragma in this file rather than by -mavx2 on a file of its own: the
// inline functions of the headers (Eigen's, Backscatter's) then stay baseline code, so no copy of
// them built for AVX2 can stand in for the baseline one elsewhere in the program.
#include "packet_returns.hpp"

#include <cstring>
#include <utility>

#include <immintrin.h>

namespace trainsim::lidar::detail {

namespace sse2 {
namespace {

constexpr int kFloats = 4, kDoubles = 2;
using vf = float __attribute__((vector_size(16)));
using vi = std::int32_t __attribute__((vector_size(16)));
using vd = double __attribute__((vector_size(16)));
using v2f = float __attribute__((vector_size(8)));
constexpr vi kLaneBits{1, 2, 4, 8};

vf sqrtF(vf x) {
  return __builtin_bit_cast(vf, _mm_sqrt_ps(__builtin_bit_cast(__m128, x)));
}
unsigned bitsF(vi mask) {
  return static_cast<unsigned>(_mm_movemask_ps(__builtin_bit_cast(__m128, mask)));
}
unsigned bitsD(decltype(vd{} < vd{}) mask) {
  return static_cast<unsigned>(_mm_movemask_pd(__builtin_bit_cast(__m128d, mask)));
}
// Lanes k, k + 1 as doubles.
vd widen(vf x, int k) {
  return k == 0 ? __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), vd)
                : __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), vd);
}
vf narrow(vd lo, vd hi) {
  const v2f a = __builtin_convertvector(lo, v2f), b = __builtin_convertvector(hi, v2f);
  return __builtin_shufflevector(a, b, 0, 1, 2, 3);
}

// Four whole points (lanes h … h + 3): the lanes' fields transposed into the points' two 16-byte
// halves, laid out as storePoint() lays them.
void storePoints(LidarPoint* to, const float* x, const float* y, const float* z,
                 const float* intensity, const float* range, const RayPacket& q, int h,
                 std::int32_t column) {
  __m128 a = _mm_load_ps(x), b = _mm_load_ps(y), c = _mm_load_ps(z), d = _mm_load_ps(intensity);
  _MM_TRANSPOSE4_PS(a, b, c, d);
  // cls | material << 16 (return index 0), by lane.
  const __m128i labels = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q.cls + h));
  const __m128i materials = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q.material + h));
  __m128 e = _mm_load_ps(range),
         f = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q.object + h))),
         g = _mm_castsi128_ps(_mm_setr_epi32(column, column + 1, column + 2, column + 3)),
         k = _mm_castsi128_ps(_mm_unpacklo_epi16(labels, materials));
  _MM_TRANSPOSE4_PS(e, f, g, k);
  auto* out = reinterpret_cast<float*>(to);
  _mm_store_ps(out, a);
  _mm_store_ps(out + 4, e);
  _mm_store_ps(out + 8, b);
  _mm_store_ps(out + 12, f);
  _mm_store_ps(out + 16, c);
  _mm_store_ps(out + 20, g);
  _mm_store_ps(out + 24, d);
  _mm_store_ps(out + 28, k);
}

#include "packet_returns_kernel.inc"

}  // namespace
}  // namespace sse2

#pragma GCC push_options
#pragma GCC target("avx2")
namespace avx2 {
namespace {

constexpr int kFloats = 8, kDoubles = 4;
using vf = float __attribute__((vector_size(32)));
using vi = std::int32_t __attribute__((vector_size(32)));
using vd = double __attribute__((vector_size(32)));
using v4f = float __attribute__((vector_size(16)));
constexpr vi kLaneBits{1, 2, 4, 8, 16, 32, 64, 128};

vf sqrtF(vf x) {
  return __builtin_bit_cast(vf, _mm256_sqrt_ps(__builtin_bit_cast(__m256, x)));
}
unsigned bitsF(vi mask) {
  return static_cast<unsigned>(_mm256_movemask_ps(__builtin_bit_cast(__m256, mask)));
}
unsigned bitsD(decltype(vd{} < vd{}) mask) {
  return static_cast<unsigned>(_mm256_movemask_pd(__builtin_bit_cast(__m256d, mask)));
}
// Lanes k … k + 3 as doubles.
vd widen(vf x, int k) {
  return k == 0 ? __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1, 2, 3), vd)
                : __builtin_convertvector(__builtin_shufflevector(x, x, 4, 5, 6, 7), vd);
}
vf narrow(vd lo, vd hi) {
  const v4f a = __builtin_convertvector(lo, v4f), b = __builtin_convertvector(hi, v4f);
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}

// Eight whole points: the eight fields' lanes transposed (an 8 × 8 transpose of 32-bit words)
// into the points' 32 bytes, laid out as storePoint() lays them.
void storePoints(LidarPoint* to, const float* x, const float* y, const float* z,
                 const float* intensity, const float* range, const RayPacket& q, int /*h*/,
                 std::int32_t column) {
  const __m256i labels =
      _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q.cls)));
  const __m256i materials =
      _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q.material)));
  const __m256 r0 = _mm256_load_ps(x), r1 = _mm256_load_ps(y), r2 = _mm256_load_ps(z),
               r3 = _mm256_load_ps(intensity), r4 = _mm256_load_ps(range),
               r5 = _mm256_castsi256_ps(
                   _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q.object))),
               r6 = _mm256_castsi256_ps(_mm256_add_epi32(
                   _mm256_set1_epi32(column), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7))),
               r7 = _mm256_castsi256_ps(_mm256_or_si256(labels, _mm256_slli_epi32(materials, 16)));
  const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1),
               t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3),
               t4 = _mm256_unpacklo_ps(r4, r5), t5 = _mm256_unpackhi_ps(r4, r5),
               t6 = _mm256_unpacklo_ps(r6, r7), t7 = _mm256_unpackhi_ps(r6, r7);
  // s_j: fields 0–3 (s0–s3) or 4–7 (s4–s7) of points j and j + 4.
  const __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xEE),
               s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xEE),
               s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xEE),
               s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xEE);
  auto* out = reinterpret_cast<float*>(to);
  _mm256_store_ps(out, _mm256_permute2f128_ps(s0, s4, 0x20));
  _mm256_store_ps(out + 8, _mm256_permute2f128_ps(s1, s5, 0x20));
  _mm256_store_ps(out + 16, _mm256_permute2f128_ps(s2, s6, 0x20));
  _mm256_store_ps(out + 24, _mm256_permute2f128_ps(s3, s7, 0x20));
  _mm256_store_ps(out + 32, _mm256_permute2f128_ps(s0, s4, 0x31));
  _mm256_store_ps(out + 40, _mm256_permute2f128_ps(s1, s5, 0x31));
  _mm256_store_ps(out + 48, _mm256_permute2f128_ps(s2, s6, 0x31));
  _mm256_store_ps(out + 56, _mm256_permute2f128_ps(s3, s7, 0x31));
}

#include "packet_returns_kernel.inc"

}  // namespace
}  // namespace avx2
#pragma GCC pop_options

bool avx2Returns() {
  static const bool have = __builtin_cpu_supports("avx2") != 0;
  return have;
}

std::size_t packetReturns(const PacketSetup& setup, const RayPacket& packet, std::size_t c0,
                          std::size_t lanes, const double* noise, const std::uint8_t* kept,
                          LidarPoint* points, float* keys, Isa isa) {
  if (isa == Isa::kAvx2 || (isa == Isa::kBest && avx2Returns()))
    return avx2::returns(setup, packet, c0, lanes, noise, kept, points, keys);
  return sse2::returns(setup, packet, c0, lanes, noise, kept, points, keys);
}

}  // namespace trainsim::lidar::detail
