#include "trainsim/lidar/intensity.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::lidar {

double reflectivity(const scene::Material& m, double cos_theta) {
  if (cos_theta <= 0.0 || cos_theta < m.cos_max_incidence)
    return 0.0;
  const double c2 = cos_theta * cos_theta;
  const double m2 = m.roughness * m.roughness;
  const double specular =
      m.k_s > 0.0 ? m.k_s * std::exp(-(1.0 - c2) / c2 / m2) / (m2 * c2 * c2) : 0.0;
  return m.reflectance * (m.k_d * cos_theta + specular) / (m.k_d + m.k_s / m2);
}

double scaledIntensity(double r, double range_m, bool range_falloff, IntensityScale scale) {
  if (range_falloff)
    r *= (10.0 / range_m) * (10.0 / range_m);
  switch (scale) {
    case IntensityScale::kUnit:
      return std::clamp(r, 0.0, 1.0);
    case IntensityScale::kVlp16:
      return r <= 1.0 ? std::round(100.0 * r)
                      : std::min(255.0, std::round(101.0 + 154.0 * (r - 1.0)));
  }
  return r;
}

}  // namespace trainsim::lidar
