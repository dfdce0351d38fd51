#pragma once
// Exposure and sensor noise on an 8-bit sRGB image, worked in linear light.
#include <cstdint>

namespace trainsim::camera {

/// 8-bit sRGB values to linear light (0..1) and back, by tables made once.
struct Srgb {
  static double toLinear(std::uint8_t value);
  /// The nearest 8-bit value of linear light `l` (clamped to 0..1).
  static std::uint8_t fromLinear(double l);
};

/// Develops 8-bit sRGB values: each is decoded to linear light (IEC 61966-2-1), multiplied by
/// the exposure's gain (2 for one stop more), given Gaussian sensor noise in linear 8-bit steps
/// (read noise σ_r, and shot noise σ_s at white, growing as the square root of the signal:
/// σ² = σ_r² + σ_s² · v / 255 for a linear value v in 0..255), clipped at white and encoded back.
/// Scaling the encoded values instead, as a plain multiply would, brightens a mid grey by two
/// stops for one and clips the sky at once.
class Exposure {
 public:
  Exposure(double gain, double read_noise_dn, double shot_noise_dn);
  /// The developed value of `srgb`; `z` a standard normal draw (unused without noise).
  std::uint8_t operator()(std::uint8_t srgb, double z) const;
  bool noisy() const { return read2_ > 0.0 || shot2_ > 0.0; }
  /// Nothing to do: gain 1 and no noise.
  bool identity() const { return gain_ == 1.0 && !noisy(); }

 private:
  double gain_, read2_, shot2_;
};

/// sRGB decoding and encoding of one channel, 0..1 both ways.
double srgbToLinear(double c);
double linearToSrgb(double l);

}  // namespace trainsim::camera
