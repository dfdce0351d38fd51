// The LiDAR's scanner against analytic scenes built here: noise, intensity, range and incidence
// limits, the blind zone, the vehicle's body, motion distortion, ring order and thread
// independence (the presets: lidar_scan_pattern_test.cpp; beam divergence:
// lidar_divergence_test.cpp; Embree's side: lidar_ray_scene_test.cpp).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>

#include "lidar_test_poses.hpp"
#include "support/scene_shapes.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/lidar/intensity.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/lidar/scan_pattern.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim {
namespace {

using lidar::Ray;
using lidar::RayHit;
using test::fixedPose;
using test::makeTile;
using test::square;

constexpr double kDeg = std::numbers::pi / 180.0;

// A closed room of planes around the sensor: every ray of a uniform pattern hits.
std::shared_ptr<const scene::Tile> room(const Eigen::Vector3d& O, double half,
                                        scene::MaterialId mat = scene::mat::kConcrete) {
  std::vector<scene::Mesh> walls;
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0}) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = 1.0;
      walls.push_back(square(s * half * e, -s * e, half * 1.01, scene::cls::kBuilding, mat));
    }
  return makeTile(O, std::move(walls));
}

lidar::LidarParams uniformParams(int channels, int columns) {
  lidar::LidarParams p;
  p.pattern = lidar::uniformPattern(channels, 15.0, -25.0, columns, 10.0);
  p.pattern.range_min_m = 0.5;
  p.pattern.range_max_m = 200.0;
  p.range_sigma_m = 0.0;
  p.motion_distortion = false;
  return p;
}

TEST(Scanner, RangeNoiseHasTheConfiguredSigma) {
  const Eigen::Vector3d O(5.0e5, 5.0e5, 0.0);
  const auto tile = room(O, 30.0);
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p = uniformParams(64, 2048);
  const lidar::Scanner clean(p);
  p.range_sigma_m = 0.05;
  const lidar::Scanner noisy(p);
  const RandomStream random(7, "lidar/test");
  const auto a = clean.scan(scene, fixedPose(O), random, 3);
  const auto b = noisy.scan(scene, fixedPose(O), random, 3);
  ASSERT_EQ(a.points.size(), static_cast<std::size_t>(64 * 2048));
  ASSERT_EQ(b.points.size(), a.points.size());
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const double e = b.points[i].range_m - a.points[i].range_m;
    sum += e;
    sum2 += e * e;
  }
  const double n = static_cast<double>(a.points.size());
  const double sigma = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(sigma, 0.05, 0.03 * 0.05);
  EXPECT_NEAR(sum / n, 0.0, 5.0 * 0.05 / std::sqrt(n));
}

TEST(Scanner, IntensityIsTheClosedFormLambertianBeckmannValue) {
  // Under a horizontal floor the normal is exact; the closed form is evaluated at each ray's
  // own (float) direction.
  for (const scene::MaterialId mat : {scene::mat::kConcrete, scene::mat::kRailHead,
                                      scene::mat::kGrass, scene::mat::kGalvanisedSteel}) {
    const Eigen::Vector3d O(0, 0, 0);
    const auto tile = makeTile(O, {square({0, 0, -2.0}, {0, 0, 1}, 500.0, scene::cls::kRail, mat)});
    lidar::RayWorld world;
    const auto scene = world.scene({tile});
    lidar::LidarParams p = uniformParams(16, 360);
    p.pattern = lidar::uniformPattern(16, -2.0, -60.0, 360, 10.0);
    p.pattern.range_max_m = 200.0;
    for (const auto scale : {lidar::IntensityScale::kUnit, lidar::IntensityScale::kVlp16}) {
      p.scale = scale;
      for (const bool falloff : {false, true}) {
        p.range_falloff = falloff;
        const lidar::Scanner scanner(p);
        const auto frame = scanner.scan(scene, fixedPose(O), RandomStream(1, "x"), 0);
        ASSERT_GT(frame.points.size(), 1000u);
        const scene::Material& m = scene::material(mat);
        for (const auto& pt : frame.points) {
          const Eigen::Vector3d d = pt.xyz.cast<double>().normalized();
          const double c = std::abs(d.z()), tan2 = (1 - c * c) / (c * c);
          const double m2 = m.roughness * m.roughness;
          double r =
              m.reflectance * (m.k_d * c + m.k_s * std::exp(-tan2 / m2) / (m2 * c * c * c * c));
          if (std::acos(c) > m.max_incidence_rad)
            r = 0.0;
          if (falloff)
            r *= 100.0 / (pt.range_m * pt.range_m);
          const double expected = scale == lidar::IntensityScale::kUnit ? std::min(1.0, r)
                                  : r <= 1.0
                                      ? std::round(100.0 * r)
                                      : std::min(255.0, std::round(101.0 + 154.0 * (r - 1.0)));
          ASSERT_NEAR(pt.intensity, expected, 1e-6 * std::max(1.0, expected))
              << m.name << " at " << std::acos(c) / kDeg << " deg, " << pt.range_m << " m, scale "
              << static_cast<int>(scale) << ", falloff " << falloff;
        }
      }
    }
  }
}

TEST(Intensity, OneSystemConstantForEveryMaterialSoGlossySurfacesKeepTheirDiffuseShare) {
  // A 100 % Lambertian target seen head-on returns 1; every material, wherever its specular
  // lobe has died away, returns its diffuse share ρ k_d cos θ (a polished rail head seen from a
  // roof at 80° returns 0.35 · 0.3 · cos 80°, not a hundredth of it), and head-on at least ρ.
  scene::Material white;
  white.reflectance = 1.0;
  white.k_d = 1.0;
  white.k_s = 0.0;
  white.roughness = 1.0;
  white.cos_max_incidence = 0.0;
  EXPECT_DOUBLE_EQ(lidar::reflectivity(white, 1.0), 1.0);
  for (const scene::Material& m : scene::materials()) {
    if (m.reflectance == 0.0)
      continue;
    EXPECT_GE(lidar::reflectivity(m, 1.0), m.reflectance * (1 - 1e-12)) << m.name;
    for (double deg = 1.0; deg < 90.0; deg += 1.0) {
      const double c = std::cos(deg * kDeg), t = std::tan(deg * kDeg);
      if (c < m.cos_max_incidence || t * t / (m.roughness * m.roughness) < 40.0)
        continue;  // no return, or still in the specular lobe (exp(−40) = 4e-18)
      EXPECT_NEAR(lidar::reflectivity(m, c), m.reflectance * m.k_d * c, 1e-12)
          << m.name << " at " << deg << " deg";
    }
  }
}

TEST(Scanner, NoReturnBeyondRangeOrPastTheMaximumIncidenceAngle) {
  const Eigen::Vector3d O(0, 0, 0);
  lidar::LidarParams p = uniformParams(1, 720);
  p.pattern = lidar::uniformPattern(1, 0.0, 0.0, 720, 10.0);
  p.pattern.range_max_m = 120.0;
  const lidar::Scanner scanner(p);
  // A wall facing the sensor at 110 m is seen, at 130 m not.
  for (const double d : {110.0, 130.0}) {
    const auto tile = makeTile(O, {square({d, 0, 0}, {-1, 0, 0}, 20.0)});
    lidar::RayWorld world;
    const auto frame = scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(1, "x"), 0);
    EXPECT_EQ(frame.points.empty(), d > 120.0);
    for (const auto& pt : frame.points)
      EXPECT_LE(pt.range_m, 120.0f);
  }
  // Retro-reflective sheeting returns up to 60°: a wall turned 55° is seen, 65° not.
  for (const double turn : {55.0, 65.0}) {
    const Eigen::Vector3d n(-std::cos(turn * kDeg), std::sin(turn * kDeg), 0);
    const auto tile =
        makeTile(O, {square({10, 0, 0}, n, 0.5, scene::cls::kSignal, scene::mat::kRetroreflector)});
    lidar::RayWorld world;
    const auto frame = scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(1, "x"), 0);
    EXPECT_EQ(frame.points.empty(), turn > 60.0) << turn;
  }
}

TEST(Scanner, AReturnIsLostBeyondTheRangeItsReflectivityReaches) {
  // A concrete floor 2 m under the sensor, seen at every range and incidence: with a 10 % target
  // detected to 25 m, each pulse returns iff its reflectivity ρ (the intensity of the unlimited
  // scan) is at least 0.1 (R / 25 m)², received power falling as ρ / R². The same through the
  // echoes of several sub-rays a pulse.
  const Eigen::Vector3d O(0, 0, 0);
  const auto tile = makeTile(O, {square({0, 0, -2.0}, {0, 0, 1}, 500.0)});
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  for (const int sub_rays : {1, 4}) {
    SCOPED_TRACE(sub_rays);
    lidar::LidarParams p = uniformParams(32, 360);
    p.pattern = lidar::uniformPattern(32, -1.0, -60.0, 360, 10.0);
    p.pattern.range_max_m = 200.0;
    p.sub_rays = sub_rays;
    p.divergence_rad = 0.0;  // every sub-ray on the axis: the echo's reflectivity is ρ
    const auto all = lidar::Scanner(p).scan(scene, fixedPose(O), RandomStream(1, "x"), 0);
    p.range_10_percent_m = 25.0;
    const auto near = lidar::Scanner(p).scan(scene, fixedPose(O), RandomStream(1, "x"), 0);
    std::map<std::pair<int, int>, const lidar::LidarPoint*> kept;
    for (const auto& b : near.points)
      kept[{b.ring, b.column}] = &b;
    std::size_t lost = 0, returned = 0;
    for (const auto& a : all.points) {
      const double rho = a.intensity, R = a.range_m, least = 0.1 * (R / 25.0) * (R / 25.0);
      ASSERT_LT(rho, 1.0);  // not clamped
      const auto b = kept.find({a.ring, a.column});
      if (std::abs(rho - least) < 1e-5 * least)
        continue;  // on the limit, within float rounding
      if (rho > least) {
        ASSERT_NE(b, kept.end()) << "lost at " << R << " m, reflectivity " << rho;
        EXPECT_EQ(b->second->range_m, a.range_m);
        ++returned;
      } else {
        EXPECT_EQ(b, kept.end()) << "returned at " << R << " m, reflectivity " << rho;
        ++lost;
      }
    }
    EXPECT_GT(returned, 1000u);
    EXPECT_GT(lost, 1000u);
    EXPECT_EQ(near.points.size() + lost, all.points.size());
  }
}

TEST(Scanner, ASurfaceNearerThanTheMinimumRangeBlocksItsBeams) {
  // A post ahead, before a wall 10 m ahead (its edges well away from any beam); the minimum range 2
  // m. At 1 m the post's beams return nothing (a real receiver is blind that near, and the post is
  // opaque); the others return the wall. At 3 m the post is seen. Each beam's outcome is worked out
  // here from the geometry. The post's edges lie 0.5 mrad inside the beams at ±16.5°: with
  // divergence (footprint radius 1.5 mrad) those two pulses straddle the edge, and with the post in
  // the blind zone they return the wall from the part of their footprint that passes it.
  const Eigen::Vector3d O(2.0e5, 1.0e5, 0.0);
  const double edge = 16.5 * kDeg + 0.0005, radius = 0.0015;
  for (const int sub_rays : {1, 16})
    for (const double post : {1.0, 3.0}) {
      SCOPED_TRACE(::testing::Message() << sub_rays << " sub-rays, post at " << post << " m");
      lidar::LidarParams p = uniformParams(1, 720);
      p.pattern = lidar::uniformPattern(1, 0.0, 0.0, 720, 10.0);
      p.pattern.range_min_m = 2.0;
      p.sub_rays = sub_rays;
      p.divergence_rad = 2.0 * radius;
      const lidar::Scanner scanner(p);
      const auto tile =
          makeTile(O, {square({post, 0, 0}, {-1, 0, 0}, post * std::tan(edge), scene::cls::kPole),
                       square({10, 0, 0}, {-1, 0, 0}, 15.0)});
      lidar::RayWorld world;
      const auto frame = scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(1, "x"), 0);
      std::size_t wall = 0, posts = 0;
      for (int c = 0; c < 720; ++c) {
        const Eigen::Vector3d& d = scanner.direction(c, 0);
        if (d.x() <= 0.0)
          continue;
        const double a = std::atan(std::abs(d.y() / d.x()));
        posts += a <= edge;
        wall += a > edge && a <= std::atan(1.5);
      }
      ASSERT_GT(posts, 60u);
      std::size_t seen_posts = 0, seen_wall = 0;
      for (const auto& pt : frame.points) {
        EXPECT_GE(pt.range_m, 2.0f);
        const double a = std::atan2(std::abs(pt.xyz.y()), pt.xyz.x());
        if (pt.cls == scene::cls::kPole) {
          ++seen_posts;
          EXPECT_NEAR(pt.xyz.x(), post, 1e-3);
        } else {
          ++seen_wall;
          // With divergence the echo's range is its footprint's mean, placed on the beam's axis.
          EXPECT_NEAR(pt.xyz.x(), 10.0, sub_rays > 1 ? 10.0 * std::tan(a) * radius : 1e-3);
          EXPECT_GT(a, edge - radius) << "the wall through the post";
        }
      }
      if (post < 2.0) {
        EXPECT_EQ(seen_posts, 0u);
        EXPECT_EQ(seen_wall, wall + (sub_rays > 1 ? 2 : 0));
      } else {
        EXPECT_EQ(seen_posts + seen_wall, posts + wall) << "one return a pulse";
        EXPECT_GE(seen_posts, posts - (sub_rays > 1 ? 2 : 0));
      }
    }
}

TEST(Scanner, TheVehicleHidesWhatLiesBehindItAndReturnsNothingOfItself) {
  // A sensor 0.2 m above a train's roof, on the roof's front edge (the default train.body), over
  // flat ground, turned on its mount by 0° and 30°. The reference is written independently of
  // the scanner's slab test: from above, a ray can only enter the box through its roof, so a
  // beam is hidden exactly when it crosses the roof's plane within the roof's rectangle.
  const Eigen::Vector3d O(3.0e5, -2.0e5, 0.0);
  const double height = 4.0, roof = 3.8, front = 10.0, length = 24.0, half_width = 1.45;
  const auto tile = makeTile(
      O, {square({0, 0, -height}, {0, 0, 1}, 400.0, scene::cls::kTerrain, scene::mat::kGrass)});
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  for (const double yaw_deg : {0.0, 30.0}) {
    // 2047 columns: none fires exactly along the roof's front edge (azimuth 90° or 270°), where
    // the sensor's double and float directions could fall either side of it.
    lidar::LidarParams p = uniformParams(64, 2047);
    lidar::LidarParams::Vehicle v;
    v.box = Eigen::AlignedBox3d(Eigen::Vector3d(front - length, -half_width, 0.0),
                                Eigen::Vector3d(front, half_width, roof));
    v.sensor_pose.linear() = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()).matrix();
    v.sensor_pose.translation() = Eigen::Vector3d(front, 0.0, height);
    p.vehicle = v;
    const lidar::Scanner scanner(p);
    const auto hidden = [&](const Eigen::Vector3d& d_sensor) {
      const Eigen::Vector3d d = v.sensor_pose.linear() * d_sensor;
      if (d.z() >= 0.0)
        return false;
      const double t = (height - roof) / -d.z();
      const double x = front + t * d.x(), y = t * d.y();
      return x >= front - length && x <= front && std::abs(y) <= half_width;
    };
    std::size_t expected = 0, hidden_beams = 0;
    for (int c = 0; c < 2047; ++c)
      for (int l = 0; l < 64; ++l) {
        const Eigen::Vector3d& d = scanner.direction(c, l);
        const bool ground = d.z() < 0.0 && height / -d.z() <= p.pattern.range_max_m;
        hidden_beams += ground && hidden(d);
        expected += ground && !hidden(d);
      }
    const auto frame = scanner.scan(scene, fixedPose(O), RandomStream(1, "x"), 0);
    EXPECT_EQ(frame.points.size(), expected) << yaw_deg;
    EXPECT_GT(hidden_beams, 20'000u) << "the roof hides a good part of the downward beams";
    for (const auto& pt : frame.points) {
      const Eigen::Vector3d d = pt.xyz.cast<double>().normalized();
      ASSERT_FALSE(hidden(d)) << pt.xyz.transpose();
      EXPECT_NEAR(pt.range_m, height / -d.z(), 1e-3);
    }
  }
  // A sensor inside the body is a configuration error.
  lidar::LidarParams p = uniformParams(16, 360);
  p.vehicle = lidar::LidarParams::Vehicle{
      Eigen::AlignedBox3d(Eigen::Vector3d(-10, -1.5, 0), Eigen::Vector3d(10, 1.5, 3.8)),
      Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 3.0))};
  EXPECT_THROW(lidar::Scanner{p}, ConfigError);
}

TEST(Scanner, MotionDistortionShiftsEachColumnByTheDistanceTravelled) {
  // A sensor running at 30 m/s along x past a wall at y = 10 m: each column is cast from where
  // the sensor is at its firing time, so its deskewed points lie v·t further along x than the
  // static frame's, and still on the wall. A wall behind it at x = −20 m, which the scan's first
  // and last columns see (it starts and ends facing backwards), keeps its deskewed points at
  // x = −20 m. 1000 columns (not a multiple of the 16 between the poses asked for), and poses
  // known over the revolution only, as the run's are: beyond its end the sensor stands (the
  // last eight columns moved at half speed when the scan asked there).
  const Eigen::Vector3d O(2.0e5, 0, 0);
  const auto tile = makeTile(
      O, {square({0, 10.0, 0}, {0, -1, 0}, 200.0), square({-20.0, 0, 0}, {1, 0, 0}, 200.0)});
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p = uniformParams(4, 1000);
  p.pattern = lidar::uniformPattern(4, 2.0, -2.0, 1000, 10.0);
  const double v = 30.0;
  const double revolution = p.pattern.revolution();
  const lidar::PoseAt moving = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = O + Eigen::Vector3d(v * std::clamp(t, 0.0, revolution), 0, 0);
    return T;
  };
  const lidar::Scanner static_scanner(p);
  p.motion_distortion = true;
  const lidar::Scanner moving_scanner(p);
  const auto still = static_scanner.scan(scene, moving, RandomStream(1, "x"), 0);
  const auto run = moving_scanner.scan(scene, moving, RandomStream(1, "x"), 0);
  ASSERT_GT(run.points.size(), 1000u);
  // The static frame's point of each pulse (the two differ where a beam passes the walls'
  // corner or leaves the range between them).
  std::map<std::pair<int, int>, const lidar::LidarPoint*> at_rest;
  for (const auto& a : still.points)
    at_rest[{a.ring, a.column}] = &a;
  double worst_offset = 0.0, worst_wall = 0.0, worst_back = 0.0, worst_measured = 0.0;
  std::size_t last_columns = 0, paired = 0;
  for (const auto& b : run.points) {
    const float t = moving_scanner.time(b);
    const auto side = [](const lidar::LidarPoint& q) {  // nearer the side wall than the back one
      return std::abs(q.xyz.y() - 10.0) < std::abs(q.xyz.x() + 20.0);
    };
    if (side(b)) {
      worst_wall = std::max(worst_wall, std::abs(b.xyz.y() - 10.0));
      const auto a = at_rest.find({b.ring, b.column});
      if (a != at_rest.end() && side(*a->second)) {
        EXPECT_EQ(static_scanner.time(*a->second), t);
        worst_offset = std::max(worst_offset, std::abs((b.xyz.x() - a->second->xyz.x()) - v * t));
        ++paired;
      }
    } else {
      worst_back = std::max(worst_back, std::abs(b.xyz.x() + 20.0));
      last_columns += b.column >= 992;
    }
    // The measured point is where the sensor saw it, from where it was.
    worst_measured =
        std::max(worst_measured, std::abs(moving_scanner.measured(b).x() + v * t - b.xyz.x()));
  }
  EXPECT_GT(paired, 1000u);
  EXPECT_LT(worst_offset, 1e-3);
  EXPECT_LT(worst_wall, 1e-3);
  EXPECT_LT(worst_back, 1e-3);
  EXPECT_LT(worst_measured, 1e-3);
  EXPECT_GE(last_columns, 32u);  // the last 8 columns, all 4 lasers on the back wall
}

TEST(Scanner, AFrameIsTheSameOnOneThreadAndOnTwo) {
  const Eigen::Vector3d O(1.0e6, 0, 0);
  const auto tile = room(O, 25.0);
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p = uniformParams(32, 1024);
  p.range_sigma_m = 0.02;
  p.dropout = 0.1;
  p.motion_distortion = true;
  const lidar::Scanner scanner(p);
  const auto pose = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = O + Eigen::Vector3d(20.0 * t, 1.0, 0.5);
    T.linear() = attitude(0.3 * t, 0.0, 0.0);
    return T;
  };
  std::vector<lidar::LidarPoint> one, two;
  tbb::task_arena(1).execute(
      [&] { one = scanner.scan(scene, pose, RandomStream(9, "l"), 5).points; });
  tbb::task_arena(2).execute(
      [&] { two = scanner.scan(scene, pose, RandomStream(9, "l"), 5).points; });
  ASSERT_EQ(one.size(), two.size());
  EXPECT_LT(one.size(), static_cast<std::size_t>(32 * 1024));  // dropout took some
  EXPECT_GT(one.size(), static_cast<std::size_t>(32 * 1024 * 8 / 10));
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(std::memcmp(one[i].xyz.data(), two[i].xyz.data(), sizeof(float) * 3), 0);
    ASSERT_EQ(one[i].range_m, two[i].range_m);
    ASSERT_EQ(one[i].ring, two[i].ring);
  }
}

// Ctrl-C during a scan: the columns not yet cast are skipped and the scan throws Cancelled;
// the scanner then scans as before, and an unset flag changes nothing.
TEST(Scanner, ACancelledScanStopsPartWayAndTheNextScanIsWhole) {
  const Eigen::Vector3d O(1.0e6, 0, 0);
  const auto tile = room(O, 25.0);
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p = uniformParams(32, 4096);
  p.motion_distortion = true;  // the pose is asked for along the scan: the test's clock
  const lidar::Scanner scanner(p);
  std::atomic<bool> cancel = false;
  std::atomic<int> asked = 0;
  const auto pose = [&](double t) {
    if (++asked == 20)
      cancel = true;  // the user presses Ctrl-C part-way through
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = O + Eigen::Vector3d(20.0 * t, 1.0, 0.5);
    return T;
  };
  const RandomStream random(9, "l");
  lidar::LidarFrame frame;
  EXPECT_THROW(scanner.scan(scene, pose, random, 5, frame, &cancel), Cancelled);
  // A task of 64 columns asks for two poses a 16-column anchor: 4096 columns would ask for 512
  // or more; the tasks started before the flag (one per thread) finish, the rest are skipped,
  // and no ring is cast.
  EXPECT_LT(asked.load(), 20 + 2 * 2 * 4);
  cancel = false;
  const auto whole = scanner.scan(scene, pose, random, 5);
  lidar::LidarFrame again;
  scanner.scan(scene, pose, random, 5, again, &cancel);
  ASSERT_EQ(again.points.size(), whole.points.size());
  EXPECT_GT(whole.points.size(), static_cast<std::size_t>(32 * 4096 * 9 / 10));
  for (std::size_t i = 0; i < whole.points.size(); ++i) {
    ASSERT_EQ(std::memcmp(again.points[i].xyz.data(), whole.points[i].xyz.data(), 12), 0);
    ASSERT_EQ(again.points[i].range_m, whole.points[i].range_m);
    ASSERT_EQ(again.points[i].ring, whole.points[i].ring);
    ASSERT_EQ(again.points[i].column, whole.points[i].column);
  }
}

TEST(Scanner, PointsComeRingByRingCounterClockwiseFromTheForwardAxis) {
  const Eigen::Vector3d O(0, 0, 0);
  const auto tile = room(O, 20.0);
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  const lidar::Scanner scanner(uniformParams(8, 512));
  const auto frame = scanner.scan(scene, fixedPose(O), RandomStream(1, "x"), 0);
  ASSERT_EQ(frame.points.size(), 8u * 512u);
  // The quadrant rule KITTI tools use splits rings where the azimuth passes +x.
  int rings = 1;
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    const auto& pt = frame.points[i];
    EXPECT_EQ(pt.ring, i / 512);
    if (i == 0)
      continue;
    const auto& prev = frame.points[i - 1];
    if (prev.xyz.x() >= 0 && prev.xyz.y() < 0 && pt.xyz.x() > 0 && pt.xyz.y() >= 0)
      ++rings;
    if (i % 512 == 0)
      continue;
    const double a0 = std::atan2(prev.xyz.y(), prev.xyz.x()),
                 a1 = std::atan2(pt.xyz.y(), pt.xyz.x());
    const double a0p = a0 < 0 ? a0 + 2 * std::numbers::pi : a0;
    const double a1p = a1 < 0 ? a1 + 2 * std::numbers::pi : a1;
    EXPECT_GT(a1p, a0p);
  }
  EXPECT_EQ(rings, 8);
  // Ring 0 is the highest beam.
  EXPECT_GT(frame.points.front().xyz.z(), frame.points.back().xyz.z());
}

TEST(Scanner, AnAzimuthWindowScansWithinItAtItsFiringTimesFromItsRightEdgeToItsLeft) {
  // A 90 deg window of a 720-column revolution on a sensor running at 30 m/s along x towards a
  // wall 20 m ahead, with walls 15 m to either side: the window's columns fire from 3/8 to 5/8 of
  // the revolution, so each point is cast from where the sensor is then; deskewed to the scan's
  // start it lies on its wall, and as measured v·t short of it. Each ring runs unbroken from the
  // window's right edge to its left (counter-clockwise from the rear).
  const Eigen::Vector3d O(3.0e5, 0, 0);
  const auto tile =
      makeTile(O, {square({20.0, 0, 0}, {-1, 0, 0}, 60.0), square({0, 15.0, 0}, {0, -1, 0}, 60.0),
                   square({0, -15.0, 0}, {0, 1, 0}, 60.0)});
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p = uniformParams(8, 720);
  p.pattern = lidar::windowed(lidar::uniformPattern(8, 5.0, -5.0, 720, 10.0), 90.0);
  p.motion_distortion = true;
  ASSERT_EQ(p.pattern.columns, 181);  // k = 270 ... 450
  const double v = 30.0, revolution = p.pattern.revolution();
  const lidar::PoseAt moving = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = O + Eigen::Vector3d(v * std::clamp(t, 0.0, revolution), 0, 0);
    return T;
  };
  const lidar::Scanner scanner(p);
  const auto frame = scanner.scan(scene, moving, RandomStream(1, "x"), 0);
  ASSERT_EQ(frame.points.size(), 8u * 181u);
  double worst_wall = 0.0, worst_measured = 0.0, worst_azimuth = 0.0;
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    const auto& pt = frame.points[i];
    EXPECT_EQ(pt.ring, i / 181);
    const double t = scanner.time(pt);
    ASSERT_GE(t, 0.375 * revolution - 1e-12);
    ASSERT_LE(t, 0.625 * revolution + 1e-12);
    const Eigen::Vector3f m = scanner.measured(pt);
    const double azimuth = std::atan2(m.y(), m.x()) / kDeg;
    worst_azimuth = std::max(worst_azimuth, std::abs(azimuth));
    const double ahead = std::abs(pt.xyz.x() - 20.0), aside = std::abs(std::abs(pt.xyz.y()) - 15.0);
    worst_wall = std::max(worst_wall, std::min(ahead, aside));
    if (ahead < aside)  // on the wall ahead
      worst_measured = std::max(worst_measured, std::abs(m.x() + v * t - 20.0));
    if (i % 181 != 0) {  // azimuth rising along the ring, from −45 to +45 deg
      const auto& prev = frame.points[i - 1];
      EXPECT_GT(std::atan2(pt.xyz.y(), pt.xyz.x()), std::atan2(prev.xyz.y(), prev.xyz.x()));
    }
  }
  EXPECT_NEAR(worst_azimuth, 45.0, 1e-5);  // float points
  EXPECT_LT(worst_wall, 1e-3);
  EXPECT_LT(worst_measured, 1e-3);
  EXPECT_GT(worst_measured, 0.0);
}

}  // namespace
}  // namespace trainsim
