#pragma once
// Backscatter intensity by the Lambertian-Beckmann model (sensors-reference.md 3.2, after Tian
// et al. 2021 as the TrainSim paper uses it).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::lidar {

/// How an intensity is written.
enum class IntensityScale : std::uint8_t {
  kUnit,   ///< float 0..1 (KITTI .bin): the reflectivity, clamped at 1
  kVlp16,  ///< Velodyne calibrated reflectivity: 0..100 diffuse, 101..255 retro-reflectors
};

/// A material's backscatter as a function of the incidence angle θ (cos θ given, 0 < cos θ ≤ 1),
/// the Lambertian-Beckmann form of sensors-reference.md 3.2:
///   ρ · (k_d cos θ + k_s exp(−tan²θ / m²) / (m² cos⁴θ)),
/// 0 past the material's maximum incidence angle (no return). The system constant is fixed once
/// for all materials, by a 100 % Lambertian target seen head-on returning 1; not per material:
/// normalising each material by its own head-on value would scale its diffuse part down by
/// (k_d + k_s / m²) / k_d, 100 × for a polished rail head (m 0.15), and leave it near black at
/// every angle but the specular one. A glossy surface is bright near normal incidence (a rail
/// head or a galvanised mast head-on can pass 1, as real sensors saturate on them) and returns
/// its diffuse share ρ k_d cos θ elsewhere. The constants are worked out once per material (the
/// LiDAR evaluates it for every return), and the angle test is a select rather than a branch: a
/// column's misses (cos θ = 0) and grazing hits come out as 0 without a misprediction each.
class alignas(32) Backscatter {  // its four constants are one 32-byte line
 public:
  Backscatter() = default;
  explicit Backscatter(const scene::Material& m)
      : cos_max_(m.cos_max_incidence),
        inv_m2_(1.0 / (m.roughness * m.roughness)),
        diffuse_(m.reflectance * m.k_d),
        specular_(m.reflectance * m.k_s * inv_m2_) {}
  double operator()(double cos_theta) const {
    const double c2 = cos_theta * cos_theta;
    const double specular =
        specular_ > 0.0 ? specular_ * std::exp(-(1.0 - c2) * inv_m2_ / c2) / (c2 * c2) : 0.0;
    const double r = diffuse_ * cos_theta + specular;
    return cos_theta > 0.0 && cos_theta >= cos_max_ ? r : 0.0;
  }
  /// The constants of the form above, for an evaluation over several returns at once:
  /// cos θ_max, 1 / m², ρ k_d and ρ k_s / m².
  double cosMax() const { return cos_max_; }
  double invM2() const { return inv_m2_; }
  double diffuse() const { return diffuse_; }
  double specular() const { return specular_; }

 private:
  double cos_max_ = 1.0, inv_m2_ = 1.0, diffuse_ = 0.0, specular_ = 0.0;
};

/// The material's backscatter at incidence angle θ (see Backscatter).
inline double reflectivity(const scene::Material& m, double cos_theta) {
  return Backscatter(m)(cos_theta);
}

/// Reflectivity r as written: kUnit clamps it to 0..1, kVlp16 maps r ≤ 1 to 100 r and r > 1 to
/// 101 + 154 (r − 1), at most 255.
inline double scaled(double r, IntensityScale scale) {
  switch (scale) {
    case IntensityScale::kUnit:
      return std::clamp(r, 0.0, 1.0);
    case IntensityScale::kVlp16:
      return r <= 1.0 ? std::round(100.0 * r)
                      : std::min(255.0, std::round(101.0 + 154.0 * (r - 1.0)));
  }
  return r;
}
/// The intensity written for a return of reflectivity r at range R: with `range_falloff`,
/// r · (10 m / R)² (raw intensity, 1/R² of an extended target, equal to r at 10 m), otherwise r
/// (calibrated reflectivity, as Velodyne reports it); then scaled().
inline double scaledIntensity(double r, double range_m, bool range_falloff, IntensityScale scale) {
  if (range_falloff)
    r *= (10.0 / range_m) * (10.0 / range_m);
  return scaled(r, scale);
}

}  // namespace trainsim::lidar
