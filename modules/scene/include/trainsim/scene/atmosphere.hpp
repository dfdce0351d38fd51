#pragma once
// Fog as the cameras and the LiDARs see it: one layer, the same for both.
#include <cmath>
#include <limits>

namespace trainsim::scene {

/// Koschmieder's constant: the visibility V at which a black object's contrast against the
/// horizon falls to 2 % is ln(50) / β, so the extinction is β = 3.912 / V. Taken as wavelength-
/// independent for fog (its droplets are far larger than both visible light's and a LiDAR's
/// 0.9 µm: Kim et al. 2001 give no wavelength dependence below 500 m of visibility).
inline constexpr double kKoschmieder = 3.912;

/// The extinction coefficient (1/m) of fog of meteorological visibility `visibility_m`.
inline double fogExtinction(double visibility_m) {
  return kKoschmieder / visibility_m;
}

/// The optical depth from a sensor to `range_m` along a ray of elevation sine `sin_elevation`,
/// through fog of extinction `extinction` at the sensor thinning with height: by e for every
/// `height_m` above the sensor, and the same as at the sensor below it. A ray rising at
/// elevation e crosses β L (1 − e^(−a)) / a of it, a = L sin e / H; a level or falling one β L.
inline double fogDepth(double extinction, double height_m, double range_m, double sin_elevation) {
  const double a = range_m * sin_elevation / height_m;
  return extinction * range_m * (a > 1e-12 ? -std::expm1(-a) / a : 1.0);
}

/// The same to the sky (no surface): β H / sin e for a rising ray, infinite for another (all
/// the fog there is below the horizon).
inline double fogDepthToSky(double extinction, double height_m, double sin_elevation) {
  return sin_elevation > 0.0 ? extinction * height_m / sin_elevation
                             : std::numeric_limits<double>::infinity();
}

}  // namespace trainsim::scene
