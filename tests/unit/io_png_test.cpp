// PNG encoding: every content preset is lossless, and 16-bit samples keep their byte order.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "trainsim/io/png.hpp"

namespace trainsim::io {
namespace {

using Contents = std::vector<PngContent>;
const Contents kAll = {PngContent::kImage, PngContent::kMeasurement, PngContent::kLabels,
                       PngContent::kLibpngDefault};

// A width × height image with what the presets are tuned for and against: flat areas, smooth
// ramps, edges, and noise (a fixed LCG, so that no filter predicts it).
template <typename T>
std::vector<T> pattern(int width, int height, int channels) {
  std::vector<T> out;
  std::uint32_t lcg = 12345;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width * channels; ++x) {
      lcg = lcg * 1664525u + 1013904223u;
      const std::uint32_t v = y < height / 3       ? (x / 7 % 3) * 40000u  // flat runs
                              : y < 2 * height / 3 ? 97u * x + 131u * y    // ramps
                                                   : lcg >> 8;             // noise
      out.push_back(static_cast<T>(v));
    }
  return out;
}

TEST(Png, EveryContentPresetRoundTripsExactly) {
  const int w = 123, h = 45;
  const auto gray16 = pattern<std::uint16_t>(w, h, 1);
  const auto gray8 = pattern<std::uint8_t>(w, h, 1);
  const auto rgb = pattern<std::uint8_t>(w, h, 3);
  for (const PngContent content : kAll) {
    SCOPED_TRACE(static_cast<int>(content));
    const PngImage a = decodePng(encodePngGray16(w, h, gray16, content));
    EXPECT_EQ(a.width, w);
    EXPECT_EQ(a.height, h);
    EXPECT_EQ(a.depth, 16);
    EXPECT_EQ(a.channels, 1);
    EXPECT_EQ(std::vector<std::uint16_t>(a.samples16.begin(), a.samples16.end()), gray16);
    const PngImage b = decodePng(encodePngGray8(w, h, gray8, content));
    EXPECT_EQ(b.depth, 8);
    EXPECT_EQ(std::vector<std::uint8_t>(b.samples8.begin(), b.samples8.end()), gray8);
    const PngImage c = decodePng(encodePngRgb8(w, h, rgb, content));
    EXPECT_EQ(c.channels, 3);
    EXPECT_EQ(std::vector<std::uint8_t>(c.samples8.begin(), c.samples8.end()), rgb);
  }
}

TEST(Png, AWrongPixelCountIsRefused) {
  const std::vector<std::uint8_t> short_image(10);
  EXPECT_THROW(encodePngGray8(4, 4, short_image, PngContent::kLabels), std::exception);
  EXPECT_THROW(encodePngRgb8(2, 2, short_image), std::exception);
}

}  // namespace
}  // namespace trainsim::io
