// The LiDAR presets against their datasheet and driver tables: each laser's elevation and
// azimuth offset, the columns a revolution holds, the firing times, and the rings' order.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "trainsim/core/error.hpp"
#include "trainsim/lidar/scan_pattern.hpp"

namespace trainsim {
namespace {

// Transcribed from sensors-reference.md 1.1, 1.2, 1.4 (S3 'xiesc') and 1.5, in laser id order.
const std::vector<double> kVlp16Elevation = {-15.0, 1.0, -13.0, 3.0,  -11.0, 5.0,  -9.0, 7.0,
                                             -7.0,  9.0, -5.0,  11.0, -3.0,  13.0, -1.0, 15.0};
const std::vector<double> kHdl32Elevation = {
    -30.67, -9.33,  -29.33, -8.0,   -28.0,  -6.67, -26.67, -5.33,  -25.33, -4.0,   -24.0,
    -2.67,  -22.67, -1.33,  -21.33, 0.0,    -20.0, 1.33,   -18.67, 2.67,   -17.33, 4.0,
    -16.0,  5.33,   -14.67, 6.67,   -13.33, 8.0,   -12.0,  9.33,   -10.67, 10.67};
const std::vector<double> kHdl64Elevation = {
    -7.23,   -6.849,  0.204,   0.591,   -6.56,   -6.19,   -8.563,  -8.219,  -5.889,  -5.483,
    -7.943,  -7.552,  -3.119,  -2.792,  -5.135,  -4.809,  -2.488,  -2.091,  -4.53,   -4.157,
    -1.81,   -1.459,  -3.819,  -3.469,  0.895,   1.293,   -1.143,  -0.756,  1.562,   1.96,
    -0.452,  -0.089,  -22.358, -21.976, -11.295, -10.754, -21.491, -21.064, -24.555, -24.147,
    -20.429, -19.892, -23.549, -22.966, -16.274, -15.906, -19.247, -18.923, -15.385, -14.927,
    -18.429, -17.964, -14.291, -13.806, -17.368, -16.801, -10.176, -9.744,  -13.163, -12.83,
    -9.3,    -8.775,  -12.294, -11.913};
const std::vector<double> kHdl64AzimuthCorrection = {
    -4.382, -2.253, 3.441,  5.683,  -0.055, 2.191,  -0.876, 1.39,   4.214, 6.485, 3.412,
    5.676,  -4.34,  -2.123, -5.133, -2.907, -0.107, 2.147,  -0.871, 1.371, 4.162, 6.385,
    3.405,  5.613,  -4.388, -2.172, -5.184, -2.94,  -0.11,  2.109,  -0.89, 1.334, -7.326,
    -3.812, 5.073,  8.335,  -0.291, 3.11,   -1.613, 1.818,  6.538,  9.944, 5.48,  8.903,
    -7.112, -3.675, -8.521, -4.989, -0.39,  3.004,  -1.626, 1.824,  6.277, 9.67,  5.178,
    8.521,  -6.933, -3.685, -8.3,   -4.884, -0.342, 2.899,  -1.572, 1.664};
const std::vector<double> kOs1Altitude = {
    16.611,  16.084,  15.557,  15.029,  14.502,  13.975,  13.447, 12.92,   12.393,  11.865,
    11.338,  10.811,  10.283,  9.756,   9.229,   8.701,   8.174,  7.646,   7.119,   6.592,
    6.064,   5.537,   5.01,    4.482,   3.955,   3.428,   2.9,    2.373,   1.846,   1.318,
    0.791,   0.264,   -0.264,  -0.791,  -1.318,  -1.846,  -2.373, -2.9,    -3.428,  -3.955,
    -4.482,  -5.01,   -5.537,  -6.064,  -6.592,  -7.119,  -7.646, -8.174,  -8.701,  -9.229,
    -9.756,  -10.283, -10.811, -11.338, -11.865, -12.393, -12.92, -13.447, -13.975, -14.502,
    -15.029, -15.557, -16.084, -16.611};
const std::vector<double> kOs1BeamAzimuth = {
    3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055,
    -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,
    -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,
    1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164,
    3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055,
    -3.164, 3.164,  1.055,  -1.055, -3.164, 3.164,  1.055,  -1.055, -3.164};

// One OS1-128's beam_intrinsics (ouster-sdk tests/pcaps/OS-1-128_v2.3.0_1024x10.json), in beam
// order: Ouster publishes no design table for 128 beams.
const std::vector<double> kOs1_128Altitude = {
    20.95,  20.67,  20.36,  20.03,  19.73,  19.41,  19.11,  18.76,  18.47,  18.14,  17.82,  17.5,
    17.19,  16.86,  16.53,  16.2,   15.89,  15.56,  15.23,  14.9,   14.57,  14.23,  13.9,   13.57,
    13.25,  12.91,  12.57,  12.22,  11.9,   11.55,  11.2,   10.87,  10.54,  10.18,  9.84,   9.51,
    9.15,   8.81,   8.47,   8.11,   7.78,   7.43,   7.08,   6.74,   6.39,   6.04,   5.7,    5.34,
    4.98,   4.64,   4.29,   3.93,   3.58,   3.24,   2.88,   2.53,   2.17,   1.82,   1.47,   1.12,
    0.78,   0.41,   0.07,   -0.28,  -0.64,  -0.99,  -1.35,  -1.7,   -2.07,  -2.4,   -2.75,  -3.11,
    -3.46,  -3.81,  -4.15,  -4.5,   -4.86,  -5.22,  -5.57,  -5.9,   -6.27,  -6.61,  -6.97,  -7.3,
    -7.67,  -8.01,  -8.35,  -8.69,  -9.05,  -9.38,  -9.71,  -10.07, -10.42, -10.76, -11.09, -11.43,
    -11.78, -12.12, -12.46, -12.78, -13.15, -13.46, -13.8,  -14.12, -14.48, -14.79, -15.11, -15.46,
    -15.79, -16.12, -16.45, -16.76, -17.11, -17.44, -17.74, -18.06, -18.39, -18.72, -19.02, -19.32,
    -19.67, -19.99, -20.27, -20.57, -20.92, -21.22, -21.54, -21.82};
const std::vector<double> kOs1_128BeamAzimuth = {
    4.21,  1.41,  -1.4,  -4.22, 4.22,  1.41,  -1.4,  -4.23, 4.21,  1.4,   -1.42, -4.2,  4.22,
    1.41,  -1.4,  -4.23, 4.21,  1.41,  -1.41, -4.21, 4.22,  1.4,   -1.41, -4.2,  4.22,  1.42,
    -1.4,  -4.2,  4.22,  1.41,  -1.42, -4.21, 4.22,  1.41,  -1.4,  -4.21, 4.2,   1.4,   -1.4,
    -4.22, 4.21,  1.41,  -1.41, -4.21, 4.22,  1.41,  -1.4,  -4.21, 4.21,  1.41,  -1.4,  -4.21,
    4.2,   1.41,  -1.4,  -4.21, 4.2,   1.4,   -1.41, -4.21, 4.22,  1.4,   -1.4,  -4.21, 4.22,
    1.42,  -1.4,  -4.2,  4.2,   1.42,  -1.4,  -4.22, 4.22,  1.41,  -1.4,  -4.2,  4.23,  1.41,
    -1.4,  -4.2,  4.21,  1.41,  -1.4,  -4.21, 4.21,  1.41,  -1.4,  -4.21, 4.22,  1.41,  -1.39,
    -4.21, 4.23,  1.41,  -1.39, -4.22, 4.23,  1.4,   -1.4,  -4.2,  4.21,  1.41,  -1.41, -4.2,
    4.22,  1.42,  -1.39, -4.22, 4.24,  1.41,  -1.41, -4.22, 4.23,  1.41,  -1.39, -4.21, 4.23,
    1.41,  -1.39, -4.2,  4.23,  1.4,   -1.39, -4.2,  4.22,  1.42,  -1.39, -4.2};

// sensors-reference.md 1.3 (the VeloView calibration's angles). Its azimuths are printed the
// other way round from the calibration's rot_correction (laser 0: +0.0244 rad), which is what
// the driver adds and what the preset holds.
const std::vector<double> kVlp32cElevation = {
    -25.0,  -1.0,   -1.667, -15.639, -11.31, 0.0,    -0.667, -8.843, -7.254, 0.333,  -0.333,
    -6.148, -5.333, 1.333,  0.667,   -4.0,   -4.667, 1.667,  1.0,    -3.667, -3.333, 3.333,
    2.333,  -2.667, -3.0,   7.0,     4.667,  -2.333, -2.0,   15.0,   10.333, -1.333};
const std::vector<double> kVlp32cAzimuthAsPrinted = {
    -1.4, 4.2, -1.4, 1.4, -1.4, 1.4, -4.2, 1.4, -1.4, 4.2, -1.4, 1.4, -4.2, 1.4, -4.2, 1.4,
    -1.4, 4.2, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4, -1.4, 1.4, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4};

TEST(LidarPresets, ReproduceTheirDatasheetTables) {
  struct Case {
    const char* name;
    const std::vector<double>* elevation;
    const std::vector<double>* azimuth;
    double azimuth_sign;
    int columns_at_10_hz;
  };
  const std::vector<double> zeros16(16, 0.0), zeros32(32, 0.0);
  const Case cases[] = {{"vlp16", &kVlp16Elevation, &zeros16, 1.0, 1808},
                        {"hdl32", &kHdl32Elevation, &zeros32, 1.0, 2170},
                        {"hdl64", &kHdl64Elevation, &kHdl64AzimuthCorrection, 1.0, 2083},
                        {"os1_64", &kOs1Altitude, &kOs1BeamAzimuth, -1.0, 1024},
                        {"vlp32c", &kVlp32cElevation, &kVlp32cAzimuthAsPrinted, -1.0, 1808},
                        {"os1_128", &kOs1_128Altitude, &kOs1_128BeamAzimuth, -1.0, 1024}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const lidar::ScanPattern p = lidar::preset(c.name, 10.0);
    ASSERT_EQ(p.lasers.size(), c.elevation->size());
    EXPECT_EQ(p.columns, c.columns_at_10_hz);
    for (std::size_t l = 0; l < p.lasers.size(); ++l) {
      EXPECT_EQ(p.lasers[l].elevation_deg, (*c.elevation)[l]);
      EXPECT_EQ(p.lasers[l].azimuth_offset_deg, c.azimuth_sign * (*c.azimuth)[l]);
      // Ring 0 is the highest laser; rings follow elevation.
      for (std::size_t m = 0; m < p.lasers.size(); ++m) {
        if ((*c.elevation)[m] > (*c.elevation)[l]) {
          EXPECT_LT(p.lasers[m].ring, p.lasers[l].ring);
        }
      }
    }
    // Column azimuths: 180° at column 0, falling by 360°/W per column (a clockwise head), each
    // laser turned by its offset and by the head's turn during its firing delay.
    for (int col : {0, 1, p.columns / 3, p.columns - 1})
      for (std::size_t l = 0; l < p.lasers.size(); ++l)
        EXPECT_NEAR(p.azimuthDeg(col, static_cast<int>(l)),
                    180.0 - 360.0 * col / p.columns - 3600.0 * p.lasers[l].time_offset_s +
                        c.azimuth_sign * (*c.azimuth)[l],
                    1e-9);
  }
  // The VLP-16 fires its lasers 2.304 µs apart (manual §9.4).
  const lidar::ScanPattern v = lidar::preset("vlp16");
  for (std::size_t l = 0; l < 16; ++l)
    EXPECT_NEAR(v.lasers[l].time_offset_s, 2.304e-6 * static_cast<double>(l), 1e-12);
  // The VLP-32C fires its lasers in pairs, 2.304 µs apart (the driver's 32C timing table).
  const lidar::ScanPattern u = lidar::preset("vlp32c");
  for (std::size_t l = 0; l < 32; ++l)
    EXPECT_NEAR(u.lasers[l].time_offset_s, 2.304e-6 * static_cast<double>(l / 2), 1e-12);
  EXPECT_THROW(lidar::preset("hdl65"), ConfigError);
}

TEST(LidarPresets, AnAzimuthWindowFiresTheRevolutionsColumnsWithinIt) {
  // The HDL-64E at 10 Hz (2083 columns, 0.173 deg apart; none looks exactly forward) within
  // windows of 120, 1 and 0.1 deg: its scan columns are exactly the revolution's whose azimuth
  // 180 − 360 k / N lies within ±fov / 2, at their own azimuths and firing times.
  const lidar::ScanPattern whole = lidar::preset("hdl64", 10.0);
  ASSERT_EQ(whole.columns, 2083);
  EXPECT_TRUE(whole.wholeRevolution());
  for (const double fov : {120.0, 1.0, 0.1}) {
    SCOPED_TRACE(fov);
    const lidar::ScanPattern w = lidar::windowed(whole, fov);
    EXPECT_EQ(w.revolutionColumns(), 2083);
    std::vector<int> inside;
    for (int k = 0; k < 2083; ++k)
      if (std::abs(180.0 - 360.0 * k / 2083.0) <= 0.5 * fov)
        inside.push_back(k);
    ASSERT_EQ(w.columns, static_cast<int>(inside.size()));
    if (inside.empty())
      continue;
    EXPECT_FALSE(w.wholeRevolution());
    EXPECT_EQ(w.first_column, inside.front());
    for (int c = 0; c < w.columns; ++c)
      for (int l : {0, 31, 63}) {
        EXPECT_EQ(w.azimuthDeg(c, l), whole.azimuthDeg(inside[static_cast<std::size_t>(c)], l));
        EXPECT_EQ(w.firingTime(c, l), whole.firingTime(inside[static_cast<std::size_t>(c)], l));
      }
  }
  EXPECT_EQ(lidar::windowed(whole, 120.0).columns, 694);  // 2083 / 3, rounded
  EXPECT_EQ(lidar::windowed(whole, 0.1).columns, 0);
  // A uniform 2048-column pattern has a column straight ahead (k = 1024): a 0.1 deg window
  // holds it alone, at azimuth 0 and half a revolution's time.
  const lidar::ScanPattern u =
      lidar::windowed(lidar::uniformPattern(4, 2.0, -2.0, 2048, 10.0), 0.1);
  ASSERT_EQ(u.columns, 1);
  EXPECT_EQ(u.azimuthDeg(0, 0), 0.0);
  EXPECT_EQ(u.firingTime(0, 0), 0.05);
  const lidar::ScanPattern same = lidar::windowed(whole, 360.0);
  EXPECT_EQ(same.columns, 2083);
  EXPECT_EQ(same.first_column, 0);
}

}  // namespace
}  // namespace trainsim
