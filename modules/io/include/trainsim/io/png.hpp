#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace trainsim::io {

/// What an image holds, which decides how it is compressed (lossless either way: only the
/// time and the size change). Measured on the default run's images (bench_camera's PNG table):
/// libpng's default, trying all five row filters on every row with zlib level 6, costs 2.6 ×
/// the time of one filter chosen for the content at level 4, for files of about the same size.
enum class PngContent {
  kImage,          ///< a camera image: the Up filter, level 4
  kMeasurement,    ///< depth, heights (smooth along a row): the Sub filter, level 4
  kLabels,         ///< class and instance ids (flat areas): Up, level 4, run-length when 8-bit
  kLibpngDefault,  ///< libpng's adaptive filters at level 6: the benchmark's baseline
};

/// PNG images in memory (libpng), rows top to bottom: 8- or 16-bit greyscale and 8-bit RGB.
/// The bytes go to files through writeFileAtomic. Throws RuntimeError if encoding fails or the
/// pixel count does not match.
std::string encodePngGray16(int width, int height, std::span<const std::uint16_t> pixels,
                            PngContent content);
std::string encodePngGray8(int width, int height, std::span<const std::uint8_t> pixels,
                           PngContent content);
std::string encodePngRgb8(int width, int height, std::span<const std::uint8_t> rgb,
                          PngContent content = PngContent::kImage);

/// A decoded PNG (for tests and readers): channels 1 or 3, depth 8 or 16; 16-bit samples are
/// in `samples16`, 8-bit ones in `samples8`.
struct PngImage {
  int width = 0, height = 0, channels = 0, depth = 0;
  std::string samples8;
  std::basic_string<std::uint16_t> samples16;
};
PngImage decodePng(std::string_view bytes);

}  // namespace trainsim::io
