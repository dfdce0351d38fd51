#pragma once
// Backscatter intensity by the Lambertian-Beckmann model (sensors-reference.md 3.2, after Tian
// et al. 2021 as the TrainSim paper uses it).
#include <cstdint>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::lidar {

/// How an intensity is written.
enum class IntensityScale : std::uint8_t {
  kUnit,   ///< float 0..1 (KITTI .bin): the reflectivity, clamped at 1
  kVlp16,  ///< Velodyne calibrated reflectivity: 0..100 diffuse, 101..255 retro-reflectors
};

/// The material's backscatter at incidence angle θ (cos θ given, 0 < cos θ ≤ 1):
///   ρ · (k_d cos θ + k_s exp(−tan²θ / m²) / (m² cos⁴θ)) / (k_d + k_s / m²),
/// normalised so that a surface seen head-on returns its reflectance ρ; 0 past the material's
/// maximum incidence angle (no return).
double reflectivity(const scene::Material& material, double cos_theta);

/// The intensity written for a return of reflectivity r at range R: with `range_falloff`,
/// r · (10 m / R)² (raw intensity, 1/R² of an extended target, equal to r at 10 m), otherwise r
/// (calibrated reflectivity, as Velodyne reports it); then scaled: kUnit clamps to 0..1, kVlp16
/// maps r ≤ 1 to 100 r and r > 1 to 101 + 154 (r − 1), at most 255.
double scaledIntensity(double reflectivity, double range_m, bool range_falloff,
                       IntensityScale scale);

}  // namespace trainsim::lidar
