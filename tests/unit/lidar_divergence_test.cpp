// Beam divergence against analytic scenes built here: each pulse a bundle of sub-rays across its
// footprint, a thin wire hit at the rate its coverage predicts, grazing ground as one echo, and
// strongest, last and dual returns.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lidar_test_poses.hpp"
#include "support/scene_shapes.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/lidar/scan_pattern.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim {
namespace {

using test::fixedPose;
using test::makeTile;
using test::square;

constexpr double kDeg = std::numbers::pi / 180.0;

// Beam divergence: a 12 mm wire 30 m ahead, swept by 1201 pulses whose axes pass it from
// 131 mm above to 131 mm below (0.22 mm apart), each pulse 64 sub-rays over a 3 mrad cone (a
// footprint of 45 mm radius there).
struct WireSweep {
  static constexpr double kRange = 30.0, kRadius = 0.006, kDivergence = 0.003, kWallBehind = 60.0;
  static constexpr int kChannels = 1201;
  static constexpr double kHalfFovDeg = 0.25;

  Eigen::Vector3d O{2.0e5, -3.0e5, 40.0};
  std::shared_ptr<const scene::Tile> tile;

  explicit WireSweep(bool wall) {
    scene::Wire wire;
    wire.radius_m = static_cast<float>(kRadius);
    wire.instance = 5;
    wire.points = {Eigen::Vector3f(static_cast<float>(kRange), -4.0f, 0.0f),
                   Eigen::Vector3f(static_cast<float>(kRange), 4.0f, 0.0f)};
    std::vector<scene::Mesh> meshes;
    if (wall)  // a dark wall 60 m behind the wire
      meshes.push_back(square({kRange + kWallBehind, 0, 0}, {-1, 0, 0}, 15.0, scene::cls::kBuilding,
                              scene::mat::kPaintedMetal));
    tile = makeTile(O, std::move(meshes), {wire});
  }

  // Column 1 of a 2-column uniform pattern looks along +x.
  lidar::LidarParams params(int sub_rays, lidar::LidarParams::Returns returns) const {
    lidar::LidarParams p;
    p.pattern = lidar::uniformPattern(kChannels, kHalfFovDeg, -kHalfFovDeg, 2, 10.0);
    p.pattern.range_min_m = 0.5;
    p.pattern.range_max_m = 200.0;
    p.range_sigma_m = 0.0;
    p.motion_distortion = false;
    p.sub_rays = sub_rays;
    p.divergence_rad = kDivergence;
    p.returns = returns;
    return p;
  }

  lidar::LidarFrame scan(const lidar::LidarParams& p) const {
    lidar::RayWorld world;
    const lidar::Scanner scanner(p);
    return scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(1, "wire"), 0);
  }

  // The beam axes' spacing where they pass the wire.
  static double step() { return kRange * 2.0 * std::tan(kHalfFovDeg * kDeg) / (kChannels - 1); }
};

TEST(Divergence, AThinWireIsHitAtTheRateItsFootprintCoveragePredicts) {
  const WireSweep sweep(false);
  const double footprint = WireSweep::kRange * std::tan(WireSweep::kDivergence / 2);
  double previous_rate = 0.0;
  for (const int n : {16, 64, 256, 1024}) {
    const auto frame = sweep.scan(sweep.params(n, lidar::LidarParams::Returns::kStrongest));
    int hits = 0;
    double covered = 0.0;
    ASSERT_EQ(frame.coverage.size(), frame.points.size());
    for (std::size_t i = 0; i < frame.points.size(); ++i) {
      const auto& pt = frame.points[i];
      if (pt.xyz.x() < 0)
        continue;  // column 0 looks backwards at nothing
      ASSERT_EQ(pt.cls, scene::cls::kWire);
      ASSERT_EQ(frame.instance(pt), 5u);
      EXPECT_NEAR(pt.range_m, WireSweep::kRange, 2 * WireSweep::kRadius);
      EXPECT_GT(frame.coverage[i], 0.0f);
      EXPECT_LE(frame.coverage[i], 1.0f);
      ++hits;
      covered += frame.coverage[i];
    }
    // A pulse sees the wire while its footprint overlaps it: axes within footprint + radius.
    const double rate = hits * WireSweep::step();
    const double predicted = 2.0 * (footprint + WireSweep::kRadius);
    // Few sub-rays leave the footprint's rim thinly sampled, so the rate converges from below
    // as they grow (measured 0.905, 0.943, 0.986, 0.995 for 16, 64, 256, 1024): the benchmark's
    // sub-rays → hit rate → time trade.
    EXPECT_LE(rate / predicted, 1.0 + 1e-9) << n;
    EXPECT_GT(rate / predicted, previous_rate) << n;
    if (n >= 256) {
      EXPECT_NEAR(rate / predicted, 1.0, 0.03) << n << " sub-rays: " << hits << " pulses";
    }
    previous_rate = rate / predicted;
    // The share of each pulse on the wire, summed over the sweep, is the wire's width whatever
    // the sampling: the footprint's whole area passes over the wire once.
    EXPECT_NEAR(covered * WireSweep::step() / (2.0 * WireSweep::kRadius), 1.0, 0.01)
        << n << " sub-rays";
  }
  // Without divergence the same sweep sees the wire only where the axis itself crosses it.
  const auto single = sweep.scan(sweep.params(1, lidar::LidarParams::Returns::kStrongest));
  int axis_hits = 0;
  for (const auto& pt : single.points)
    axis_hits += pt.xyz.x() > 0;
  EXPECT_NEAR(axis_hits * WireSweep::step() / (2.0 * WireSweep::kRadius), 1.0, 0.05);
}

// A flat ground at a grazing angle stretches each pulse's echo over metres of range (here up to
// 30 m: 5 mrad beams 1° to 5° below the horizon, 2 m above the ground), far more than the echo
// separation: it is one surface, so one echo, never a second one "behind" it; its range lies
// within the footprint's nearest and farthest ground.
TEST(Divergence, AFlatGroundAtAGrazingAngleIsOneEchoNotTwo) {
  const Eigen::Vector3d O(-4.0e5, 7.0e5, 12.0);
  constexpr double kHeight = 2.0, kDivergence = 0.005, kTop = -1.0, kBottom = -5.0;
  const auto tile = makeTile(
      O, {square({0, 0, -kHeight}, {0, 0, 1}, 400.0, scene::cls::kTerrain, scene::mat::kGrass)});
  lidar::LidarParams p;
  p.pattern = lidar::uniformPattern(33, kTop, kBottom, 64, 10.0);
  p.pattern.range_min_m = 0.5;
  p.pattern.range_max_m = 300.0;
  p.range_sigma_m = 0.0;
  p.motion_distortion = false;
  p.sub_rays = 64;
  p.divergence_rad = kDivergence;
  p.returns = lidar::LidarParams::Returns::kDual;
  lidar::RayWorld world;
  const lidar::Scanner scanner(p);
  const auto frame = scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(3, "ground"), 0);
  ASSERT_EQ(frame.points.size(), static_cast<std::size_t>(33 * 64)) << "one point a pulse";
  for (const lidar::LidarPoint& pt : frame.points) {
    ASSERT_EQ(pt.return_index, 0);
    // The point lies on its beam's axis, so its elevation is the axis's.
    const double elevation = std::asin(static_cast<double>(pt.xyz.z()) / pt.range_m);
    const double nearest = kHeight / std::sin(-elevation + 0.5 * kDivergence);
    const double farthest = kHeight / std::sin(-elevation - 0.5 * kDivergence);
    EXPECT_GE(pt.range_m, nearest * (1.0 - 1e-5));
    EXPECT_LE(pt.range_m, farthest * (1.0 + 1e-5));
  }
}

TEST(Divergence, DualReturnsReportTheWireAndTheWallBehindIt) {
  const WireSweep sweep(true);
  using Returns = lidar::LidarParams::Returns;
  const auto dual = sweep.scan(sweep.params(64, Returns::kDual));
  const auto last = sweep.scan(sweep.params(64, Returns::kLast));
  const auto strongest = sweep.scan(sweep.params(64, Returns::kStrongest));
  // The points ahead (column 0 looks backwards at nothing), each with its share of its pulse.
  struct Ahead : lidar::LidarPoint {
    float coverage;
  };
  const auto ahead = [](const lidar::LidarFrame& f) {
    std::vector<Ahead> out;
    for (std::size_t i = 0; i < f.points.size(); ++i)
      if (f.points[i].xyz.x() > 0)
        out.push_back({f.points[i], f.coverage[i]});
    return out;
  };
  const auto d = ahead(dual), l = ahead(last), s = ahead(strongest);
  ASSERT_EQ(l.size(), static_cast<std::size_t>(WireSweep::kChannels)) << "every pulse";
  ASSERT_EQ(s.size(), static_cast<std::size_t>(WireSweep::kChannels));
  int second = 0;
  for (const auto& pt : l) {
    EXPECT_EQ(pt.cls, scene::cls::kBuilding) << "the last echo is the wall";
    EXPECT_NEAR(pt.range_m, WireSweep::kRange + WireSweep::kWallBehind, 0.01);
  }
  for (const auto& pt : d) {
    EXPECT_LE(pt.return_index, 1);
    if (pt.return_index == 1) {
      ++second;
      EXPECT_EQ(pt.cls, scene::cls::kBuilding);
    }
    if (pt.cls == scene::cls::kWire) {
      EXPECT_EQ(pt.return_index, 0) << "the wire is never the last echo";
      EXPECT_LT(pt.coverage, 1.0f);
    }
  }
  // Every pulse reports one point, and a second exactly where the wire is the strongest echo
  // and the wall still returns behind it.
  int wire_strongest = 0;
  for (const auto& pt : s)
    wire_strongest += pt.cls == scene::cls::kWire;
  EXPECT_GT(wire_strongest, 0);
  EXPECT_EQ(static_cast<int>(d.size()), WireSweep::kChannels + second);
  EXPECT_EQ(second, wire_strongest);
}

}  // namespace
}  // namespace trainsim
