#include "trainsim/camera/exposure.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::camera {

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double linearToSrgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

namespace {
constexpr int kEncodeSteps = 65535;  // linear steps of the encoding table: < 0.05 DN at black
}

Exposure::Exposure(double gain, double read_noise_dn, double shot_noise_dn)
    : gain_(gain),
      read2_(read_noise_dn * read_noise_dn),
      shot2_(shot_noise_dn * shot_noise_dn / 255.0),
      encode_(kEncodeSteps + 1) {
  for (int i = 0; i <= kEncodeSteps; ++i)
    encode_[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
        std::lround(255.0 * linearToSrgb(static_cast<double>(i) / kEncodeSteps)));
  for (int v = 0; v < 256; ++v)
    linear_[static_cast<std::size_t>(v)] = 255.0 * srgbToLinear(v / 255.0);
}

std::uint8_t Exposure::operator()(std::uint8_t srgb, double z) const {
  double v = gain_ * linear_[srgb];
  if (noisy())
    v += std::sqrt(read2_ + shot2_ * std::min(v, 255.0)) * z;
  const double l = std::clamp(v / 255.0, 0.0, 1.0);
  return encode_[static_cast<std::size_t>(std::lround(l * kEncodeSteps))];
}

}  // namespace trainsim::camera
