// Fog on a camera's colour image: Koschmieder's law, the object's light blended with the fog's
// by exp(-3.912 d / V) over the pixel's range d, in linear light. Checked against a second
// camera on the same mount without fog, read back from the files with the float depth and P2.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include <Eigen/Core>

#include "trainsim/camera/exposure.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

namespace fs = std::filesystem;

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// By day the fog is light grey; at night it is lit as the scene is, dark (its colour read from
// the sky's pixels, all fog in a dense fog), and the same blend holds. A dense ground fog veils
// the sky wholly; a thin haze leaves the sky's colour above the horizon.
struct Fog {
  const char* daytime;
  double visibility_m, height_m;
};
class CameraFog : public ::testing::TestWithParam<Fog> {};

TEST_P(CameraFog, ColoursFollowKoschmiederInLinearLightThroughALayerThinningWithHeight) {
  const Fog f = GetParam();
  const bool night = std::string(f.daytime) == "night";
  const scenario::Json camera = {{"width", 200},
                                 {"height", 64},
                                 {"period_ns", 1'000'000'000},
                                 {"depth_float", true},
                                 {"daytime", f.daytime}};
  scenario::Json foggy = camera;
  foggy["fog_visibility_m"] = f.visibility_m;
  foggy["fog_height_m"] = f.height_m;
  const scenario::Json input = {
      {"route", {{"source", "blocks"}, {"blocks", {{{"type", "straight"}, {"length_m", 300}}}}}},
      {"trajectory", {{"static_only", true}, {"standstill_start_s", 1}}},
      {"dataset", {{"frame_period_ns", 1'000'000'000}}},
      {"sensors", {{"cameras", {camera, foggy}}}}};
  const fs::path out = fs::temp_directory_path() /
                       fmt::format("trainsim_fog_{}_{}_{}", f.daytime, f.visibility_m, ::getpid());
  fs::remove_all(out);
  GenerateOptions options;
  options.out = out;
  generate(scenario::Scenario::resolve(input, scenarioSchema()), options);
  const fs::path seq = out / "sequences" / "00";
  const io::PngImage clear = io::decodePng(fileBytes(seq / "image_2" / "000000.png"));
  const io::PngImage fog = io::decodePng(fileBytes(seq / "image_3" / "000000.png"));
  // The float depth (PFM: a header, then rows bottom to top), 0 where nothing is drawn.
  const std::string pfm = fileBytes(seq / "depth_2" / "000000.pfm");
  const std::string header = fmt::format("Pf\n{} {}\n-1.0\n", clear.width, clear.height);
  ASSERT_EQ(pfm.substr(0, header.size()), header);
  const auto depthAt = [&](int u, int v) {
    float z = 0.0f;
    const std::size_t row = static_cast<std::size_t>(clear.height - 1 - v);
    std::memcpy(&z, pfm.data() + header.size() + 4 * (row * clear.width + u), 4);
    return static_cast<double>(z);
  };
  // P2 = K [I | 0] for camera 0: fx, cx on the first row, fy, cy on the second.
  // This run has cameras only: calib.txt still carries a Tr (KITTI's readers need one), from
  // the vehicle's body frame, whose forward axis is the forward-looking camera's z.
  double fx = 0, cx = 0, fy = 0, cy = 0;
  Eigen::Matrix<double, 3, 4> tr = Eigen::Matrix<double, 3, 4>::Zero();
  std::istringstream calib(fileBytes(seq / "calib.txt"));
  for (std::string line; std::getline(calib, line);) {
    const auto numbers = [&](std::size_t skip) {
      std::istringstream row(line.substr(skip));
      std::array<double, 12> p{};
      for (double& v : p)
        row >> v;
      return p;
    };
    if (line.starts_with("P2:")) {
      const auto p = numbers(3);
      fx = p[0], cx = p[2], fy = p[5], cy = p[6];
    }
    if (line.starts_with("Tr:")) {
      const auto p = numbers(3);
      tr = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(p.data());
    }
  }
  EXPECT_LT((tr.leftCols<3>().transpose() * tr.leftCols<3>() - Eigen::Matrix3d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
  EXPECT_GT((tr.leftCols<3>() * Eigen::Vector3d::UnitX()).z(), 0.9);
  fs::remove_all(out);
  ASSERT_GT(fx, 0.0);
  ASSERT_EQ(clear.samples8.size(), fog.samples8.size());
  // The level camera's rays, in its axes (x right, y down, z ahead), and how much of each
  // pixel's light the fog keeps: e^(−β L (1 − e^(−a)) / a), a = L s / H, over a range L rising
  // at s (sine of the elevation), e^(−β H / s) to the sky, none below the horizon.
  const double beta = 3.912 / f.visibility_m;
  const auto keepAt = [&](int u, int v) {
    const double z = depthAt(u, v);  // along the optical axis; 0: nothing drawn (sky)
    const double x = (u - cx) / fx, y = (v - cy) / fy;
    const double norm = std::sqrt(1 + x * x + y * y), s = -y / norm;
    if (z > 0.0) {
      const double range = z * norm, a = range * s / f.height_m;
      return std::exp(-beta * range * (a > 1e-9 ? (1.0 - std::exp(-a)) / a : 1.0));
    }
    return s > 0.0 ? std::exp(-beta * f.height_m / s) : 0.0;
  };
  // The fog's colour: by day the renderer's light grey, at night that of the sky's pixels where
  // the fog keeps nothing of the sky (a dense fog's), which must be one dark colour, no brighter
  // than twice the clear night sky.
  std::array<std::uint8_t, 3> kFog = {200, 204, 208};
  const auto luminance = [](const std::uint8_t* c) {
    return 0.2126 * camera::Srgb::toLinear(c[0]) + 0.7152 * camera::Srgb::toLinear(c[1]) +
           0.0722 * camera::Srgb::toLinear(c[2]);
  };
  if (night) {
    bool first = true;
    double clear_sky = 0.0;
    for (int v = 0; v < clear.height; ++v)
      for (int u = 0; u < clear.width; ++u) {
        if (depthAt(u, v) > 0.0)
          continue;
        const std::size_t i = static_cast<std::size_t>(v) * clear.width + u;
        clear_sky = std::max(
            clear_sky, luminance(reinterpret_cast<const std::uint8_t*>(&clear.samples8[3 * i])));
        if (keepAt(u, v) > 1e-4)
          continue;
        for (std::size_t ch = 0; ch < 3; ++ch) {
          const auto c = static_cast<std::uint8_t>(fog.samples8[3 * i + ch]);
          if (first)
            kFog[ch] = c;
          ASSERT_EQ(c, kFog[ch]) << "sky pixel " << u << ", " << v;
        }
        first = false;
      }
    ASSERT_FALSE(first);
    for (const std::uint8_t c : kFog)
      EXPECT_GT(c, 10);
    EXPECT_LT(luminance(kFog.data()), 2.0 * clear_sky);
  }
  int ground = 0, sky = 0, clear_sky_kept = 0;
  for (int v = 0; v < clear.height; ++v)
    for (int u = 0; u < clear.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * clear.width + u;
      const double z = depthAt(u, v), keep = keepAt(u, v);
      ++(z > 0.0 ? ground : sky);
      clear_sky_kept += z == 0.0 && keep > 0.5;
      for (int ch = 0; ch < 3; ++ch) {
        const auto c0 = static_cast<std::uint8_t>(clear.samples8[3 * i + ch]);
        const double light =
            keep * camera::Srgb::toLinear(c0) + (1.0 - keep) * camera::Srgb::toLinear(kFog[ch]);
        const int want = camera::Srgb::fromLinear(light);
        // Rounding to 8 bits on both sides: at most one step.
        ASSERT_NEAR(static_cast<std::uint8_t>(fog.samples8[3 * i + ch]), want, 1)
            << "pixel " << u << ", " << v << " at " << z << " m";
      }
    }
  EXPECT_GT(ground, 1000);
  EXPECT_GT(sky, 1000);
  // A thin haze leaves most of the sky's own light; a dense fog none.
  if (f.visibility_m >= 10000.0) {
    EXPECT_GT(clear_sky_kept, sky / 2);
  }
  if (f.visibility_m <= 1000.0) {
    EXPECT_EQ(clear_sky_kept, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(DayNightAndHaze, CameraFog,
                         ::testing::Values(Fog{"noon", 150.0, 100.0}, Fog{"night", 150.0, 100.0},
                                           Fog{"noon", 20000.0, 100.0},
                                           Fog{"noon", 3000.0, 400.0}));

// A camera 1 m above the middle of the roof looking back and 30° down sees the train's body
// (train.body) where the roof is: unlabelled, no instance, at the depth the roof plane has,
// H / (sin 30° + (v − cy) / fy · cos 30°) along the optical axis for a camera H above it. With
// the body off, the same pixels see the track beyond.
TEST(CameraBody, ACameraLookingBackAtTheRoofSeesTheTrainsBody) {
  const auto run = [](bool body) {
    const scenario::Json camera = {
        {"width", 96},
        {"height", 64},
        {"period_ns", 1'000'000'000},
        {"mount", {{"x_m", 0.0}, {"z_m", 4.8}, {"yaw_deg", 180.0}, {"pitch_deg", -30.0}}}};
    const scenario::Json input = {
        {"route", {{"source", "blocks"}, {"blocks", {{{"type", "straight"}, {"length_m", 300}}}}}},
        {"trajectory", {{"static_only", true}, {"standstill_start_s", 1}}},
        {"dataset", {{"frame_period_ns", 1'000'000'000}}},
        {"train", {{"body", {{"enabled", body}, {"roof_m", 3.8}}}}},
        {"sensors", {{"cameras", {camera}}}}};
    const fs::path out =
        fs::temp_directory_path() / fmt::format("trainsim_body_{}_{}", ::getpid(), body);
    fs::remove_all(out);
    GenerateOptions options;
    options.out = out;
    generate(scenario::Scenario::resolve(input, scenarioSchema()), options);
    const fs::path seq = out / "sequences" / "00";
    struct Images {
      io::PngImage depth, semantic, instance;
      std::string calib;
    } images{io::decodePng(fileBytes(seq / "depth_2" / "000000.png")),
             io::decodePng(fileBytes(seq / "semantic_2" / "000000.png")),
             io::decodePng(fileBytes(seq / "instance_2" / "000000.png")),
             fileBytes(seq / "calib.txt")};
    fs::remove_all(out);
    return images;
  };
  const auto with = run(true);
  const auto without = run(false);
  double fy = 0, cy = 0;  // the rows' focal length and centre, from P2
  std::istringstream calib(with.calib);
  for (std::string line; std::getline(calib, line);)
    if (line.starts_with("P2:")) {
      std::istringstream row(line.substr(3));
      std::array<double, 12> p{};
      for (double& v : p)
        row >> v;
      fy = p[5], cy = p[6];
    }
  ASSERT_GT(fy, 0.0);
  const int w = with.depth.width, h = with.depth.height;
  int roof = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      if (static_cast<std::uint8_t>(with.semantic.samples8[i]) != 0)
        continue;
      ++roof;
      const double s = std::sin(30.0 * kRadPerDeg), c = std::cos(30.0 * kRadPerDeg);
      const double expected = 1.0 / (s + (v - cy) / fy * c);
      EXPECT_NEAR(with.depth.samples16[i] / 256.0, expected, 0.01) << u << ", " << v;
      EXPECT_EQ(with.instance.samples16[i], 0) << u << ", " << v;
      EXPECT_NE(static_cast<std::uint8_t>(without.semantic.samples8[i]), 0) << u << ", " << v;
      EXPECT_GT(without.depth.samples16[i] / 256.0, expected + 1.0) << u << ", " << v;
    }
  // The roof fills the middle of the picture (2.9 m wide, seen from 1 m above).
  EXPECT_GT(roof, w * h / 4);
  const std::size_t centre = static_cast<std::size_t>(h / 2) * w + static_cast<std::size_t>(w / 2);
  EXPECT_EQ(static_cast<std::uint8_t>(with.semantic.samples8[centre]), 0);
}

}  // namespace
}  // namespace trainsim::sim
