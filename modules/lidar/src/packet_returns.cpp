#include "packet_returns.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include <emmintrin.h>

namespace trainsim::lidar::detail {
namespace {

// GCC's vector types: arithmetic and comparisons lane by lane in SSE2 registers. Written by hand
// because the compiler does not vectorise this loop by itself (its conversions between float and
// double and its square root stop it) and Eigen 3.4 converts float to double one lane at a time.
using v4f = float __attribute__((vector_size(16)));
using v4i = std::int32_t __attribute__((vector_size(16)));
using v2d = double __attribute__((vector_size(16)));
using v2f = float __attribute__((vector_size(8)));

v4f load4(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
v2d load2(const double* p) {
  v2d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void store4(float* p, v4f v) {
  std::memcpy(p, &v, sizeof v);
}
void store2(double* p, v2d v) {
  std::memcpy(p, &v, sizeof v);
}
v4f splat(float x) {
  return v4f{x, x, x, x};
}
// Lanes 0–1 and 2–3 as doubles, and back.
v2d low(v4f x) {
  return __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), v2d);
}
v2d high(v4f x) {
  return __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), v2d);
}
v4f narrow(v2d lo, v2d hi) {
  const v2f a = __builtin_convertvector(lo, v2f), b = __builtin_convertvector(hi, v2f);
  return __builtin_shufflevector(a, b, 0, 1, 2, 3);
}
v4f abs4(v4f x) {
  return std::bit_cast<v4f>(std::bit_cast<v4i>(x) & 0x7FFFFFFF);
}
v4f sqrt4(v4f x) {
  return std::bit_cast<v4f>(_mm_sqrt_ps(std::bit_cast<__m128>(x)));
}
unsigned bits4(v4i mask) {
  return static_cast<unsigned>(_mm_movemask_ps(std::bit_cast<__m128>(mask)));
}
unsigned bits2(decltype(v2d{} < v2d{}) mask) {
  return static_cast<unsigned>(_mm_movemask_pd(std::bit_cast<__m128d>(mask)));
}

// The backscatter of lanes k, k + 1 (Backscatter::operator(), lane by lane): 0 for a miss (its
// cos θ is NaN) and past the maximum incidence angle.
v2d backscatter(const Backscatter& a, const Backscatter& b, v2d c) {
  const v2d diffuse{a.diffuse(), b.diffuse()}, cos_max{a.cosMax(), b.cosMax()};
  v2d r = diffuse * c;
  if (a.specular() > 0.0 || b.specular() > 0.0) {  // most surfaces have no specular part
    const v2d c2 = c * c, inv_m2{a.invM2(), b.invM2()}, specular{a.specular(), b.specular()};
    alignas(16) double e[2];
    store2(e, -(1.0 - c2) * inv_m2 / c2);
    Eigen::Map<Eigen::Array2d, Eigen::Aligned16> exponential(e);
    exponential = exponential.exp();
    r += specular * load2(e) / (c2 * c2);  // 0 · ∞ = NaN at c = 0 is dropped below
  }
  return c > 0.0 && c >= cos_max ? r : v2d{};
}

// pseudoAzimuth() lane by lane.
v4f azimuthKeys(v4f x, v4f y) {
  const v4f d = abs4(x) + abs4(y), t = y / d;
  v4f a = x >= 0.0f ? t : 2.0f - t;
  a = (a < 0.0f ? a + 4.0f : a) + 0.0f;
  return d == 0.0f ? v4f{} : a;
}

}  // namespace

std::size_t packetReturns(const PacketSetup& s, const RayPacket& q, std::size_t c0,
                          std::size_t lanes, const double* noise, const std::uint8_t* kept,
                          LidarPoint* points, float* keys) {
  const std::size_t R = s.returns, P = s.padded;
  alignas(16) double rho[8];
  alignas(16) float range[8], x[8], y[8], z[8], intensity[8], key[8];
  unsigned ok = 0;
  for (std::size_t h = 0; h < 8; h += 4) {
    // The incidence angle, from the unnormalised normal (a miss has none: 0 / 0).
    const v4f nx = load4(q.ng_x + h), ny = load4(q.ng_y + h), nz = load4(q.ng_z + h);
    const v4f dot = nx * load4(q.dir_x + h) + ny * load4(q.dir_y + h) + nz * load4(q.dir_z + h);
    const v4f cos_theta = abs4(dot) / sqrt4(nx * nx + ny * ny + nz * nz);
    // The backscatter and the noisy range, in double.
    const v4f truth = load4(q.t_far + h);
    v2d measured[2];
    for (std::size_t k = 0; k < 4; k += 2) {
      const v2d ck = k == 0 ? low(cos_theta) : high(cos_theta),
                tk = k == 0 ? low(truth) : high(truth);
      const v2d r =
          backscatter(s.backscatter[q.material[h + k]], s.backscatter[q.material[h + k + 1]], ck);
      store2(rho + h + k, r);
      ok |= bits2(r > 0.0 && r >= s.threshold) << (h + k);
      const v2d n = R == 1 ? load2(noise + h + k) : v2d{noise[(h + k) * R], noise[(h + k + 1) * R]};
      measured[k / 2] = tk + (s.sigma0 + s.sigma1 * tk) * n;
    }
    const v4f m = narrow(measured[0], measured[1]);
    store4(range + h, m);
    ok &= ~(0xFu << h) | bits4(m >= s.range_min && m <= s.range_max) << h;
    // The point deskewed to the frame time.
    const std::size_t c = c0 + h;
    const auto field = [&](std::size_t f) { return load4(s.frames + f * P + c); };
    const v4f vx = load4(s.ax + c) * m, vy = load4(s.ay + c) * m, vz = load4(s.az + c) * m;
    const std::size_t D = s.deskew, T = s.shift;
    const v4f px = field(D) * vx + field(D + 1) * vy + field(D + 2) * vz + field(T);
    const v4f py = field(D + 3) * vx + field(D + 4) * vy + field(D + 5) * vz + field(T + 1);
    store4(x + h, px);
    store4(y + h, py);
    store4(z + h, field(D + 6) * vx + field(D + 7) * vy + field(D + 8) * vz + field(T + 2));
    store4(key + h, azimuthKeys(px, py));
    // The intensity (kUnit: the reflectivity, clamped at 1; others lane by lane).
    v2d written[2];
    for (std::size_t k = 0; k < 4; k += 2) {
      v2d r = load2(rho + h + k);
      if (s.falloff) {
        const v2d ten = 10.0 / (k == 0 ? low(m) : high(m));
        r *= ten * ten;
      }
      if (s.scale == IntensityScale::kUnit) {
        written[k / 2] = r < 0.0 ? v2d{} : r > 1.0 ? v2d{1.0, 1.0} : r;
      } else {
        alignas(16) double lane[2];
        store2(lane, r);
        written[k / 2] = v2d{scaled(lane[0], s.scale), scaled(lane[1], s.scale)};
      }
    }
    store4(intensity + h, narrow(written[0], written[1]));
  }
  for (std::size_t k = 0; k < 8; ++k)
    if (kept[k] == 0)
      ok &= ~(1u << k);
  ok &= (1u << lanes) - 1;
  if (s.directions != nullptr)  // keyed as measured: as Scanner::measured() gives them
    for (std::size_t k = 0; k < lanes; ++k) {
      const Eigen::Vector3f v =
          (s.directions[c0 + k] * static_cast<double>(range[k])).cast<float>();
      key[k] = pseudoAzimuth(v.x(), v.y());
    }

  if (lanes < 8 || R != 1) {  // the ring's last columns, or two slots a pulse
    for (std::size_t k = 0; k < lanes; ++k) {
      const std::size_t slot = (c0 + k) * R;
      keys[slot] = (ok >> k & 1u) != 0 ? key[k] : kNoReturn;
      storePoint(points[slot], {x[k], y[k], z[k]}, intensity[k], range[k], q.object[k],
                 static_cast<std::uint16_t>(c0 + k), s.ring, q.cls[k],
                 static_cast<std::uint8_t>(q.material[k]), 0);
    }
    return static_cast<std::size_t>(std::popcount(ok));
  }
  // Eight whole points, four at a time: the lanes' fields transposed into the points' two
  // 16-byte halves (laid out as storePoint() lays them), stored whether or not the lane returned
  // (an empty slot's point is not read).
  const __m128i labels = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q.cls));
  const __m128i materials = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q.material));
  // cls | material << 16 (return index 0), by lane.
  const __m128i kinds[2] = {_mm_unpacklo_epi16(labels, materials),
                            _mm_unpackhi_epi16(labels, materials)};
  for (std::size_t h = 0; h < 8; h += 4) {
    __m128 a = _mm_load_ps(x + h), b = _mm_load_ps(y + h), c = _mm_load_ps(z + h),
           d = _mm_load_ps(intensity + h);
    _MM_TRANSPOSE4_PS(a, b, c, d);
    const auto column = static_cast<std::int32_t>(c0 + h) | static_cast<std::int32_t>(s.ring) << 16;
    __m128 e = _mm_load_ps(range + h),
           f = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q.object + h))),
           g = _mm_castsi128_ps(_mm_setr_epi32(column, column + 1, column + 2, column + 3)),
           k = _mm_castsi128_ps(kinds[h / 4]);
    _MM_TRANSPOSE4_PS(e, f, g, k);
    auto* to = reinterpret_cast<__m128*>(points + c0 + h);
    _mm_store_ps(reinterpret_cast<float*>(to), a);
    _mm_store_ps(reinterpret_cast<float*>(to + 1), e);
    _mm_store_ps(reinterpret_cast<float*>(to + 2), b);
    _mm_store_ps(reinterpret_cast<float*>(to + 3), f);
    _mm_store_ps(reinterpret_cast<float*>(to + 4), c);
    _mm_store_ps(reinterpret_cast<float*>(to + 5), g);
    _mm_store_ps(reinterpret_cast<float*>(to + 6), d);
    _mm_store_ps(reinterpret_cast<float*>(to + 7), k);
    const v4i returned = (v4i{1, 2, 4, 8} & static_cast<std::int32_t>(ok >> h)) != 0;
    store4(keys + c0 + h, returned ? load4(key + h) : splat(kNoReturn));
  }
  return static_cast<std::size_t>(std::popcount(ok));
}

}  // namespace trainsim::lidar::detail
