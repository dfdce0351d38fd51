// Fog in the LiDAR's path against closed forms and an independent quadrature: the soft-target
// response of Rasshofer et al. 2011, echoes dimmed by the two-way transmission through the
// cameras' layer, surfaces fading where the fog brings them under the detectable power, the
// fog's own echo in clear sky, and how it competes with a surface's (strongest, last, dual).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "lidar_test_poses.hpp"
#include "support/scene_shapes.hpp"
#include "trainsim/lidar/fog.hpp"
#include "trainsim/lidar/intensity.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/lidar/scan_pattern.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim {
namespace {

using test::fixedPose;
using test::makeTile;
using test::square;

constexpr double kC = 299'792'458.0;

// Rasshofer's soft-target integral written out again, by 64-point Gauss-Legendre on each piece
// between the integrand's kinks (the overlap's start and end and the pulse window's start): an
// independent quadrature of the same definition.
double softResponse(const lidar::FogParams& p, double R) {
  const double alpha = 3.912 / p.visibility_m;
  const double beta = 0.046 / (std::log(20.0) / alpha);
  const double L = kC * p.pulse_half_width_ns * 1e-9;
  const auto f = [&](double r) {
    const double xi = r < p.overlap_begin_m ? 0.0
                      : r > p.overlap_full_m
                          ? 1.0
                          : (r - p.overlap_begin_m) / (p.overlap_full_m - p.overlap_begin_m);
    const double s = std::sin(std::numbers::pi * (R - r) / L);
    return s * s * xi * std::exp(-2.0 * alpha * r) / (r * r);
  };
  // Gauss-Legendre nodes by Newton's method on P_64.
  constexpr int n = 64;
  static const auto rule = [] {
    std::array<std::pair<double, double>, n> out{};
    for (int i = 0; i < n; ++i) {
      double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = pk;
        }
        dp = n * (x * p1 - p0) / (x * x - 1.0);
        const double dx = p1 / dp;
        x -= dx;
        if (std::abs(dx) < 1e-15)
          break;
      }
      out[static_cast<std::size_t>(i)] = {x, 2.0 / ((1.0 - x * x) * dp * dp)};
    }
    return out;
  }();
  std::vector<double> cuts = {std::max(p.overlap_begin_m, R - L)};
  for (const double k : {p.overlap_full_m})
    if (k > cuts.front() && k < R)
      cuts.push_back(k);
  cuts.push_back(R);
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (b <= a)
      continue;
    for (const auto& [x, w] : rule)
      sum += 0.5 * (b - a) * w * f(0.5 * (a + b) + 0.5 * (b - a) * x);
  }
  return std::numbers::pi * beta * sum;
}

lidar::FogParams fogOf(double visibility_m) {
  lidar::FogParams f;
  f.visibility_m = visibility_m;
  return f;
}

TEST(FogModel, SoftTargetResponseAgreesWithAnIndependentQuadrature) {
  for (const double V : {30.0, 100.0, 1000.0}) {
    const lidar::FogParams p = fogOf(V);
    const lidar::FogModel fog(p);
    for (const double R : {0.95, 1.5, 2.0, 3.37, 5.0, 6.5, 8.0, 12.0, 20.0}) {
      const double want = softResponse(p, R);
      EXPECT_NEAR(fog.response(R), want, 2e-5 * fog.peakPower()) << "V " << V << " R " << R;
    }
    // The peak is the largest of the quadrature's values on a 1 cm grid, found within it.
    double best = 0.0, at = 0.0;
    for (double R = 1.0; R < 20.0; R += 0.01)
      if (const double v = softResponse(p, R); v > best) {
        best = v;
        at = R;
      }
    EXPECT_NEAR(fog.peakPower(), best, 1e-4 * best);
    EXPECT_NEAR(fog.peakRange(), at, 0.015);
    // The span where the echo's range is drawn: above half the peak, and not beyond.
    EXPECT_LT(fog.nearRange(), fog.peakRange());
    EXPECT_GT(fog.farRange(), fog.peakRange());
    EXPECT_GE(softResponse(p, fog.nearRange() + 0.005), 0.5 * best);
    EXPECT_LE(softResponse(p, fog.nearRange() - 0.015), 0.5 * best);
    EXPECT_GE(softResponse(p, fog.farRange() - 0.005), 0.5 * best);
    EXPECT_LE(softResponse(p, fog.farRange() + 0.015), 0.5 * best);
    // β = 0.046 / MOR, MOR the 5 % contrast visibility: 0.046 ln(50) / (ln(20) V).
    EXPECT_NEAR(fog.backscattering(), 0.046 * 3.912 / (std::log(20.0) * V), 1e-12);
  }
}

TEST(FogModel, TransmissionFollowsTheLayerAlongTheRay) {
  lidar::FogParams p = fogOf(80.0);
  p.height_m = 12.0;
  const lidar::FogModel fog(p);
  const double alpha = 3.912 / 80.0;
  for (const double s : {-0.5, 0.0, 0.1, 0.7})
    for (const double R : {1.0, 25.0, 90.0}) {
      // ∫ α(r) dr with α(r) = α min(1, e^(−r s / H)), by Simpson's rule on 20 000 steps.
      const int n = 20000;
      const auto a = [&](double r) { return alpha * std::min(1.0, std::exp(-r * s / p.height_m)); };
      double depth = a(0.0) + a(R);
      for (int i = 1; i < n; ++i)
        depth += (i % 2 == 1 ? 4.0 : 2.0) * a(R * i / n);
      depth *= R / n / 3.0;
      EXPECT_NEAR(fog.transmission(R, s), std::exp(-2.0 * depth), 1e-12) << s << " " << R;
    }
  EXPECT_EQ(lidar::FogModel(fogOf(0.0)).transmission(50.0, 0.0), 1.0);
}

// A sensor 1000 km out looking along +x at a concrete wall square to the beam, through fog.
struct FoggyWall {
  Eigen::Vector3d O{1.0e6, 2.0e5, 30.0};

  static lidar::LidarParams params(double visibility_m, lidar::LidarParams::Returns returns) {
    lidar::LidarParams p;
    p.pattern = lidar::uniformPattern(1, 0.0, 0.0, 720, 10.0);  // one level laser, 0.5° columns
    p.pattern.range_min_m = 0.5;
    p.pattern.range_max_m = 200.0;
    p.range_sigma_m = 0.0;
    p.motion_distortion = false;
    p.returns = returns;
    p.fog = fogOf(visibility_m);
    return p;
  }

  // The points of the column looking along +x (column 360 of 720 starting behind).
  std::vector<lidar::LidarPoint> ahead(const lidar::LidarParams& p, double wall_m) const {
    lidar::RayWorld world;
    const lidar::Scanner scanner(p);
    const auto tile = makeTile(O, {square({wall_m, 0, 0}, {-1, 0, 0}, 0.05 * wall_m)});
    const lidar::LidarFrame f =
        scanner.scan(world.scene({tile}), fixedPose(O), RandomStream(3, "fog"), 0);
    std::vector<lidar::LidarPoint> out;
    for (const lidar::LidarPoint& q : f.points)
      if (std::abs(scanner.direction(q.column, 0).y()) < 1e-9 &&
          scanner.direction(q.column, 0).x() > 0.0)
        out.push_back(q);
    return out;
  }
};

TEST(Fog, AnEchoIsDimmedByItsTwoWayTransmission) {
  const FoggyWall w;
  const double rho = lidar::reflectivity(scene::material(scene::mat::kConcrete), 1.0);
  for (const double D : {5.0, 20.0, 60.0, 150.0}) {
    const auto clear = w.ahead(FoggyWall::params(0.0, lidar::LidarParams::Returns::kLast), D);
    const auto foggy = w.ahead(FoggyWall::params(200.0, lidar::LidarParams::Returns::kLast), D);
    ASSERT_EQ(clear.size(), 1u);
    ASSERT_EQ(foggy.size(), 1u) << D;
    EXPECT_EQ(foggy[0].cls, scene::cls::kBuilding);
    EXPECT_NEAR(foggy[0].range_m, D, 1e-3);
    EXPECT_NEAR(clear[0].intensity, rho, 1e-6 * rho);
    const double want = rho * std::exp(-2.0 * 3.912 / 200.0 * D);
    EXPECT_NEAR(foggy[0].intensity, want, 1e-6 * want) << D;
  }
}

TEST(Fog, ASurfaceFadesWhereTheFogTakesItUnderTheDetectablePower) {
  // ρ e^(−2 α D) / D² = detectable: the wall's range limit in fog, by bisection.
  const double V = 150.0, alpha = 3.912 / V;
  const double rho = lidar::reflectivity(scene::material(scene::mat::kConcrete), 1.0);
  lidar::LidarParams p = FoggyWall::params(V, lidar::LidarParams::Returns::kLast);
  p.range_10_percent_m = 120.0;
  const double detectable = p.detectable();
  double lo = 1.0, hi = 200.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (rho * std::exp(-2.0 * alpha * mid) / (mid * mid) >= detectable ? lo : hi) = mid;
  }
  // In clear air the same wall is detected out to 120 √(ρ / 0.1) m, far beyond.
  ASSERT_GT(120.0 * std::sqrt(rho / 0.1), 1.5 * lo);
  const FoggyWall w;
  const auto walls = [&](double D) {
    int n = 0;
    for (const auto& q : w.ahead(p, D))
      n += q.cls == scene::cls::kBuilding;
    return n;
  };
  EXPECT_EQ(walls(0.98 * lo), 1) << "limit " << lo << " m";
  EXPECT_EQ(walls(1.02 * lo), 0) << "limit " << lo << " m";
}

TEST(Fog, EveryPulseIntoTheSkyReturnsTheFogsEcho) {
  const double V = 50.0;
  lidar::LidarParams p;
  p.pattern = lidar::uniformPattern(16, 0.0, -15.0, 1000, 10.0);  // level and below: fog as dense
  p.pattern.range_min_m = 0.5;
  p.pattern.range_max_m = 120.0;
  p.range_sigma_m = 0.0;
  p.motion_distortion = false;
  p.fog = fogOf(V);
  const lidar::Scanner scanner(p);
  const lidar::FogModel& fog = scanner.fog();
  lidar::RayWorld world;
  const Eigen::Vector3d O(-4.0e5, 7.0e5, 12.0);
  const lidar::LidarFrame f =
      scanner.scan(world.scene({}), fixedPose(O), RandomStream(9, "fog"), 4);
  ASSERT_EQ(f.points.size(), 16000u);
  // Their ranges are drawn with density ∝ the response over its top: the sample's mean and
  // variance against the span's, worked out from the quadrature above.
  double n = 0.0, m1 = 0.0, m2 = 0.0;
  for (double R = fog.nearRange(); R <= fog.farRange(); R += 0.001) {
    const double w = softResponse(p.fog, R);
    n += w;
    m1 += w * R;
    m2 += w * R * R;
  }
  const double mean = m1 / n, var = m2 / n - mean * mean;
  double s1 = 0.0, s2 = 0.0;
  for (const lidar::LidarPoint& q : f.points) {
    EXPECT_EQ(q.cls, scene::cls::kFog);
    EXPECT_EQ(f.instance(q), 0u);
    EXPECT_GE(q.range_m, fog.nearRange() - 1e-4);
    EXPECT_LE(q.range_m, fog.farRange() + 1e-4);
    // Its reflectivity is the waveform's peak power at its range; the point lies on the beam.
    const double r = q.range_m;
    EXPECT_NEAR(q.intensity, std::min(1.0, fog.peakPower() * r * r), 1e-6);
    EXPECT_NEAR(q.xyz.norm(), r, 1e-4);
    s1 += r;
    s2 += r * r;
  }
  const double N = static_cast<double>(f.points.size());
  const double got = s1 / N, got_var = s2 / N - got * got;
  EXPECT_NEAR(got, mean, 4.0 * std::sqrt(var / N));
  EXPECT_NEAR(got_var, var, 0.05 * var);
  // No fog, no points.
  p.fog.visibility_m = 0.0;
  EXPECT_TRUE(lidar::Scanner(p)
                  .scan(world.scene({}), fixedPose(O), RandomStream(9, "fog"), 4)
                  .points.empty());
}

TEST(Fog, TheFogsEchoCompetesWithTheSurfacesAsEchoesDo) {
  const double V = 50.0;
  const FoggyWall w;
  const lidar::FogModel fog(fogOf(V));
  const double rho = lidar::reflectivity(scene::material(scene::mat::kConcrete), 1.0);
  using Returns = lidar::LidarParams::Returns;
  // Far: the wall's power ρ e^(−2αD) / D² is below the fog's peak, so the strongest return is
  // the fog's and the last the wall's; dual gives both, the fog's first.
  const double far = 30.0;
  ASSERT_LT(rho * std::exp(-2.0 * 3.912 / V * far) / (far * far), fog.peakPower());
  const auto strongest = w.ahead(FoggyWall::params(V, Returns::kStrongest), far);
  ASSERT_EQ(strongest.size(), 1u);
  EXPECT_EQ(strongest[0].cls, scene::cls::kFog);
  const auto last = w.ahead(FoggyWall::params(V, Returns::kLast), far);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].cls, scene::cls::kBuilding);
  const auto dual = w.ahead(FoggyWall::params(V, Returns::kDual), far);
  ASSERT_EQ(dual.size(), 2u);
  for (const auto& q : dual)
    EXPECT_EQ(q.cls, q.return_index == 0 ? scene::cls::kFog : scene::cls::kBuilding);
  // Near: the wall outshines the fog (strongest is the wall's; dual the fog's and the wall's).
  const double mid = fog.farRange() + 0.5;
  ASSERT_GT(rho * std::exp(-2.0 * 3.912 / V * mid) / (mid * mid), fog.peakPower());
  const auto bright = w.ahead(FoggyWall::params(V, Returns::kStrongest), mid);
  ASSERT_EQ(bright.size(), 1u);
  EXPECT_EQ(bright[0].cls, scene::cls::kBuilding);
  // Nearer than the fog's echo can be: the wall hides it, one point a pulse even in dual.
  const double nearest = 0.5 * (0.5 + fog.nearRange());
  const auto hidden = w.ahead(FoggyWall::params(V, Returns::kDual), nearest);
  ASSERT_EQ(hidden.size(), 1u);
  EXPECT_EQ(hidden[0].cls, scene::cls::kBuilding);
}

TEST(Fog, TheFogReturnsFromTheShareOfTheFootprintANearerWireLeavesOpen) {
  // A 12 mm wire 2.5 m ahead, nearer than the fog's echo can be, across a 10 mrad footprint of
  // 64 sub-rays: the pulse returns the wire and the fog, their shares of the footprint summing
  // to one.
  const FoggyWall w;
  scene::Wire wire;
  wire.radius_m = 0.006f;
  wire.instance = 3;
  wire.points = {Eigen::Vector3f(2.5f, -1.0f, 0.0f), Eigen::Vector3f(2.5f, 1.0f, 0.0f)};
  lidar::LidarParams p = FoggyWall::params(50.0, lidar::LidarParams::Returns::kDual);
  p.sub_rays = 64;
  p.divergence_rad = 0.01;
  const lidar::Scanner scanner(p);
  ASSERT_LT(2.5, scanner.fog().nearRange());
  lidar::RayWorld world;
  const lidar::LidarFrame f = scanner.scan(world.scene({makeTile(w.O, {}, {wire})}), fixedPose(w.O),
                                           RandomStream(3, "fog"), 0);
  ASSERT_EQ(f.coverage.size(), f.points.size());
  double wire_share = -1.0, fog_share = -1.0;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const lidar::LidarPoint& q = f.points[i];
    if (scanner.direction(q.column, 0).x() < 0.9999)
      continue;  // the pulses along +x only
    (q.cls == scene::cls::kWire ? wire_share : fog_share) = f.coverage[i];
    EXPECT_TRUE(q.cls == scene::cls::kWire || q.cls == scene::cls::kFog);
  }
  EXPECT_GT(wire_share, 0.05);
  EXPECT_GT(fog_share, 0.05);
  EXPECT_NEAR(wire_share + fog_share, 1.0, 1e-6);
}

TEST(Fog, TheSameBytesOnOneThreadOrTwo) {
  lidar::LidarParams p = FoggyWall::params(80.0, lidar::LidarParams::Returns::kDual);
  p.pattern = lidar::uniformPattern(32, 10.0, -20.0, 1024, 10.0);
  p.pattern.range_min_m = 0.5;
  p.pattern.range_max_m = 120.0;
  p.range_sigma_m = 0.02;
  p.dropout = 0.1;
  const FoggyWall w;
  const lidar::Scanner scanner(p);
  lidar::RayWorld world;
  const auto tile = makeTile(w.O, {square({25, 0, 0}, {-1, 0, 0}, 20.0)});
  const lidar::RayScene scene = world.scene({tile});
  const auto run = [&](int threads) {
    tbb::task_arena arena(threads);
    lidar::LidarFrame f;
    arena.execute([&] { f = scanner.scan(scene, fixedPose(w.O), RandomStream(5, "fog"), 7); });
    return f;
  };
  const lidar::LidarFrame one = run(1), two = run(2);
  ASSERT_EQ(one.points.size(), two.points.size());
  ASSERT_GT(one.points.size(), 10000u);
  EXPECT_EQ(std::memcmp(one.points.data(), two.points.data(),
                        one.points.size() * sizeof(lidar::LidarPoint)),
            0);
}

}  // namespace
}  // namespace trainsim
