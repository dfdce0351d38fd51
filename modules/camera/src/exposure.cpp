#include "trainsim/camera/exposure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace trainsim::camera {

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double linearToSrgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

namespace {

constexpr int kEncodeSteps = 65535;  // linear steps of the encoding table: < 0.05 DN at black

struct Tables {
  std::array<double, 256> linear{};
  std::vector<std::uint8_t> encode = std::vector<std::uint8_t>(kEncodeSteps + 1);
  Tables() {
    for (int v = 0; v < 256; ++v)
      linear[static_cast<std::size_t>(v)] = srgbToLinear(v / 255.0);
    for (int i = 0; i <= kEncodeSteps; ++i)
      encode[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
          std::lround(255.0 * linearToSrgb(static_cast<double>(i) / kEncodeSteps)));
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

}  // namespace

double Srgb::toLinear(std::uint8_t value) {
  return tables().linear[value];
}

std::uint8_t Srgb::fromLinear(double l) {
  return tables()
      .encode[static_cast<std::size_t>(std::lround(std::clamp(l, 0.0, 1.0) * kEncodeSteps))];
}

Exposure::Exposure(double gain, double read_noise_dn, double shot_noise_dn)
    : gain_(gain),
      read2_(read_noise_dn * read_noise_dn),
      shot2_(shot_noise_dn * shot_noise_dn / 255.0) {}

std::uint8_t Exposure::operator()(std::uint8_t srgb, double z) const {
  double v = gain_ * 255.0 * Srgb::toLinear(srgb);
  if (noisy())
    v += std::sqrt(read2_ + shot2_ * std::min(v, 255.0)) * z;
  return Srgb::fromLinear(v / 255.0);
}

}  // namespace trainsim::camera
