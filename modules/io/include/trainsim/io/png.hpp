#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace trainsim::io {

/// PNG images in memory (libpng), rows top to bottom: 8- or 16-bit greyscale and 8-bit RGB.
/// The bytes go to files through writeFileAtomic. Throws RuntimeError if encoding fails or the
/// pixel count does not match.
std::string encodePngGray16(int width, int height, std::span<const std::uint16_t> pixels);
std::string encodePngGray8(int width, int height, std::span<const std::uint8_t> pixels);
std::string encodePngRgb8(int width, int height, std::span<const std::uint8_t> rgb);

/// A decoded PNG (for tests and readers): channels 1 or 3, depth 8 or 16; 16-bit samples are
/// in `samples16`, 8-bit ones in `samples8`.
struct PngImage {
  int width = 0, height = 0, channels = 0, depth = 0;
  std::string samples8;
  std::basic_string<std::uint16_t> samples16;
};
PngImage decodePng(std::string_view bytes);

}  // namespace trainsim::io
