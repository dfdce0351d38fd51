// Vertical and cant profiles, design rules, the random route generator and waypoint import.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "../support/simpson_chain.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/track/route_design.hpp"

namespace trainsim::track {
namespace {

TEST(VerticalProfile, VerticalCurveIsACircleInClosedForm) {
  // Grade +10 permille, then a crest of R_v = 8000 m to -12 permille.
  const double r = 8000.0;
  const VerticalProfile p = VerticalProfile::fromPvis({{0, 0, 0}, {1000, 10, r}, {2000, -2, 0}});
  ASSERT_EQ(p.elements().size(), 3u);
  const VerticalElement& c = p.elements()[1];
  EXPECT_NEAR(1.0 / std::abs(c.curvature_1_m), r, 1e-6);
  // Centre of the circle below the curve start (crest): every point is at distance R from it.
  const double s0 = p.elementStart(1);
  const VerticalState a = p.at(s0);
  const Eigen::Vector2d centre(s0 + r * std::sin(a.pitch_rad), a.z_m - r * std::cos(a.pitch_rad));
  for (double x = 0; x <= c.length_m; x += c.length_m / 17) {
    const VerticalState v = p.at(s0 + x);
    EXPECT_NEAR((Eigen::Vector2d(s0 + x, v.z_m) - centre).norm(), r, 1e-7);
    // Tangent perpendicular to the radius.
    const Eigen::Vector2d radial = (Eigen::Vector2d(s0 + x, v.z_m) - centre) / r;
    EXPECT_NEAR(radial.dot(Eigen::Vector2d(std::cos(v.pitch_rad), std::sin(v.pitch_rad))), 0.0,
                1e-12);
    // 3D distance along the arc is R Δθ.
    EXPECT_NEAR(v.distance_m - a.distance_m, r * (a.pitch_rad - v.pitch_rad), 1e-9);
  }
  // The end of the curve lies on the second grade line.
  const double s1 = p.elementStart(2);
  EXPECT_NEAR(p.at(s1).z_m, 10.0 - 0.012 * (s1 - 1000.0), 1e-9);
  EXPECT_NEAR(std::tan(p.at(s1).pitch_rad), -0.012, 1e-12);
  // Chainage from distance inverts distance from chainage.
  for (double s = 0; s < 2000; s += 37.3)
    EXPECT_NEAR(p.chainageAt(p.at(s).distance_m), s, 1e-9);
}

TEST(VerticalProfile, OverlappingCurvesAreReducedAndReported) {
  std::vector<std::pair<std::size_t, double>> reduced;
  VerticalProfile::fromPvis({{0, 0, 0}, {100, 3, 20000}, {200, 0, 20000}, {300, 0, 0}}, &reduced);
  ASSERT_FALSE(reduced.empty());
  EXPECT_LT(reduced[0].second, 20000.0);
}

TEST(CantProfile, LinearAndBlossRamps) {
  const CantProfile lin({{100, 0.0, 0.12, RampShape::kLinear}});
  EXPECT_NEAR(lin.at(25).cant_m, 0.03, 1e-15);
  EXPECT_NEAR(lin.at(25).rate_m_per_m, 0.0012, 1e-15);
  const CantProfile bloss({{100, 0.0, 0.12, RampShape::kBloss}});
  EXPECT_NEAR(bloss.at(50).cant_m, 0.06, 1e-15);
  EXPECT_NEAR(bloss.at(0).rate_m_per_m, 0.0, 1e-15);
  EXPECT_NEAR(bloss.at(100).rate_m_per_m, 0.0, 1e-15);
  // Finite differences of the closed forms.
  for (double s = 5; s < 100; s += 9.5) {
    const double h = 1e-4;
    EXPECT_NEAR((bloss.at(s + h).cant_m - bloss.at(s - h).cant_m) / (2 * h),
                bloss.at(s).rate_m_per_m, 1e-9);
    EXPECT_NEAR((bloss.at(s + h).rate_m_per_m - bloss.at(s - h).rate_m_per_m) / (2 * h),
                bloss.at(s).rate2_1_m, 1e-9);
  }
}

TEST(DesignRules, ReferenceNumbers) {
  DesignRules r;
  // docs/REFERENCES.md R1.4: 160 km/h with D + I = 160 + 130 mm gives R_min ≈ 1042 m.
  EXPECT_NEAR(r.minRadius(160 / 3.6), 1042.0, 1.5);
  // R1.3 worked example: V 160, R 1500, D 120, I 81: L1 107 m, L2 66 m, L3 53 m.
  r.max_cant_gradient = 2.25e-3;
  const double e = r.equilibriumCant(160 / 3.6, 1500);
  EXPECT_NEAR(e, 0.2013, 1e-3);
  EXPECT_NEAR(r.minTransitionLength(160 / 3.6, 0.120, 0.0), 106.7, 0.1);
  EXPECT_NEAR(r.minTransitionLength(160 / 3.6, 0.0, e - 0.120), 65.6, 0.6);
}

RouteOptions optionsFor(double speed_kmh) {
  RouteOptions o;
  o.rules.design_speed_m_s = speed_kmh / 3.6;
  return o;
}

TEST(RouteGenerator, ThousandSeedsObeyEveryDesignRule) {
  const double speeds[] = {30, 80, 120, 160, 200, 250, 50};
  int stations = 0, tunnels = 0, bridges = 0, curves = 0;
  for (std::uint64_t seed = 0; seed < 1000; ++seed) {
    RouteGeneratorParams p;
    p.length_m = 4000 + 13.0 * static_cast<double>(seed % 200);
    RouteOptions o = optionsFor(speeds[seed % 7]);
    if (seed % 7 == 3)
      o.transition_shape = TransitionShape::kBloss;
    p.radius_max_m = std::max(4000.0, 1.5 * o.rules.minRadius(o.rules.design_speed_m_s));
    const DesignedRoute d = generateRoute(p, o, seed);
    const std::vector<Violation> v = checkDesign(d.route, o.rules);
    ASSERT_TRUE(v.empty()) << "seed " << seed << ": " << v[0].rule << " at "
                           << v[0].chainage_begin_m << " m: " << v[0].message;
    EXPECT_NEAR(d.route.track.length(), p.length_m, 1e-6);
    // Blocks tile the route.
    for (std::size_t i = 1; i < d.route.blocks.size(); ++i)
      ASSERT_DOUBLE_EQ(d.route.blocks[i].chainage_begin_m, d.route.blocks[i - 1].chainage_end_m);
    for (const Block& b : d.route.blocks) {
      stations += b.type == BlockType::kStation;
      tunnels += b.type == BlockType::kTunnel;
      bridges += b.type == BlockType::kBridge;
      curves += b.type == BlockType::kCurve;
    }
  }
  EXPECT_GT(stations, 100);
  EXPECT_GT(tunnels, 50);
  EXPECT_GT(bridges, 50);
  EXPECT_GT(curves, 1000);
}

TEST(RouteGenerator, SameSeedSameRouteDifferentSeedDifferentRoute) {
  const RouteOptions o;
  const DesignedRoute a = generateRoute({}, o, 7), b = generateRoute({}, o, 7),
                      c = generateRoute({}, o, 8);
  const double s = 3333.3;
  EXPECT_EQ(a.route.track.atChainage(s).position, b.route.track.atChainage(s).position);
  EXPECT_NE(a.route.track.atChainage(s).position, c.route.track.atChainage(s).position);
}

// A route of 1000 km: the element chain's end point and 3D length agree with an independent
// Simpson re-integration of (cos ψ, sin ψ) and 1/cos θ to well under a millimetre.
TEST(RouteGenerator, ThousandKilometresKeepSubMillimetrePrecision) {
  RouteGeneratorParams p;
  p.length_m = 1.0e6;
  const DesignedRoute d = generateRoute(p, RouteOptions{}, 99);
  const HorizontalAlignment& h = d.route.track.horizontal();
  const testing::ChainEnd ref = testing::simpsonChainEnd(h.elements(), 0, 0, 0, 1.0);
  const long double x = ref.x, y = ref.y;
  const Eigen::Vector3d end = d.route.track.atChainage(d.route.track.length()).position;
  EXPECT_LT(std::hypot(end.x() - static_cast<double>(x), end.y() - static_cast<double>(y)), 1e-3);
  // Simpson's rule of a function of the pitch over every vertical element (4 m steps).
  const VerticalProfile& v = d.route.track.vertical();
  auto integrate = [&](auto&& of_pitch) {
    long double total = 0;
    for (std::size_t i = 0; i < v.elements().size(); ++i) {
      const double a = v.elementStart(i), b = std::min(v.elementStart(i + 1), h.length());
      if (b <= a)
        continue;
      const int n = 2 * std::max(1, static_cast<int>((b - a) / 4.0));
      const long double step = (b - a) / n;
      long double sum = 0;
      for (int k = 0; k <= n; ++k) {
        const long double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        sum += w * of_pitch(v.at(a + static_cast<double>(k * step)).pitch_rad);
      }
      total += sum * step / 3;
    }
    return static_cast<double>(total);
  };
  // 3D length: ∫ 1/cos θ ds; height: ∫ tan θ ds.
  const double u = integrate([](double t) { return 1.0 / std::cos(t); });
  EXPECT_LT(std::abs(d.route.track.distanceLength() - u), 1e-3);
  const double z = integrate([](double t) { return std::tan(t); });
  EXPECT_LT(std::abs(end.z() - z), 1e-3);
}

TEST(BlockRoute, CurveGeometryIsTheGivenOneInClosedForm) {
  RouteOptions opt;
  // 300 m straight, a 1500 m left curve with an 80 m arc and given 60 m transitions and 100 mm
  // cant, a 200 m station climbing 2 permille, then a right curve with automatic transitions.
  std::vector<BlockSpec> blocks(4);
  blocks[0].length_m = 300.0;
  blocks[1] = {BlockType::kCurve, 80.0, 1500.0, Turn::kLeft, 60.0, 0.100, 0.0};
  blocks[2] = {BlockType::kStation, 200.0, 0.0, Turn::kLeft, -1.0, -1.0, 0.002};
  blocks[3] = {BlockType::kCurve, 150.0, 2000.0, Turn::kRight, -1.0, -1.0, 0.002};
  const DesignedRoute r = buildBlockRoute(blocks, opt);
  ASSERT_EQ(r.route.blocks.size(), 4u);
  const Block& c = r.route.blocks[1];
  EXPECT_EQ(c.type, BlockType::kCurve);
  EXPECT_DOUBLE_EQ(c.chainage_begin_m, 300.0);
  EXPECT_NEAR(c.chainage_end_m, 300.0 + 80.0 + 2 * 60.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.radius_m, 1500.0);
  EXPECT_DOUBLE_EQ(c.cant_m, -0.100);  // a left curve raises the right rail
  // Heading change through transition + arc + transition: L_arc/R + 2·L_t/(2R).
  const HorizontalAlignment& h = r.route.track.horizontal();
  EXPECT_NEAR(h.at(c.chainage_end_m).heading_rad, (80.0 + 60.0) / 1500.0, 1e-12);
  // Automatic transitions and cant are the rules' choice, as in the generator.
  const Block& c2 = r.route.blocks[3];
  const double cant = opt.rules.appliedCant(opt.rules.design_speed_m_s, 2000.0);
  EXPECT_DOUBLE_EQ(c2.cant_m, cant);
  EXPECT_DOUBLE_EQ(c2.radius_m, -2000.0);
  const std::vector<BlockSpec> back = blockSpecs(r.route);
  ASSERT_EQ(back.size(), 4u);
  EXPECT_DOUBLE_EQ(back[1].transition_m, 60.0);
  EXPECT_GE(back[3].transition_m, 20.0);
  EXPECT_EQ(std::fmod(back[3].transition_m, 5.0), 0.0);
  EXPECT_EQ(back[3].direction, Turn::kRight);
  // Station on a 2 permille climb, stopping the train; a vertical curve joins the grades.
  EXPECT_TRUE(r.route.blocks[2].stop);
  EXPECT_EQ(r.stops.size(), 1u);
  const double s_mid =
      0.5 * (r.route.blocks[2].chainage_begin_m + r.route.blocks[2].chainage_end_m);
  EXPECT_NEAR(std::tan(r.route.track.vertical().at(s_mid).pitch_rad), 0.002, 1e-12);
  EXPECT_NEAR(std::tan(r.route.track.vertical().at(100.0).pitch_rad), 0.0, 1e-15);
  EXPECT_TRUE(r.fitting.empty());
  // The given 60 m transitions are too short for 100 mm at 160 km/h (v·ΔD/(dD/dt) = 89 m):
  // the block list is laid out as given and the rule check names that curve alone.
  const std::vector<Violation> v = checkDesign(r.route, opt.rules);
  ASSERT_FALSE(v.empty());
  for (const Violation& x : v) {
    EXPECT_EQ(x.rule, "transition_length") << x.message;
    EXPECT_EQ(x.block_id, 1) << x.message;
  }
}

TEST(BlockRoute, GeneratedRouteRebuildsFromItsBlockList) {
  RouteOptions opt;
  RouteGeneratorParams g;
  g.length_m = 20000.0;
  for (std::uint64_t seed : {1u, 7u, 42u}) {
    const DesignedRoute gen = generateRoute(g, opt, seed);
    const DesignedRoute rebuilt = buildBlockRoute(blockSpecs(gen.route), opt);
    ASSERT_EQ(rebuilt.route.blocks.size(), gen.route.blocks.size());
    for (std::size_t i = 0; i < gen.route.blocks.size(); ++i) {
      const Block& a = gen.route.blocks[i];
      const Block& b = rebuilt.route.blocks[i];
      EXPECT_EQ(a.type, b.type);
      EXPECT_NEAR(a.chainage_end_m, b.chainage_end_m, 1e-8);
      EXPECT_DOUBLE_EQ(a.radius_m, b.radius_m);
      EXPECT_DOUBLE_EQ(a.cant_m, b.cant_m);
      EXPECT_DOUBLE_EQ(a.speed_limit_m_s, b.speed_limit_m_s);
    }
    // Same horizontal alignment: same end point and heading.
    const double len = gen.route.track.length();
    const auto ea = gen.route.track.horizontal().at(len);
    const auto eb = rebuilt.route.track.horizontal().at(len);
    EXPECT_LT((ea.position_m - eb.position_m).norm(), 1e-6);
    EXPECT_NEAR(ea.heading_rad, eb.heading_rad, 1e-12);
    // Mean grades per block keep every block end at its height.
    for (const Block& b : gen.route.blocks)
      EXPECT_NEAR(rebuilt.route.track.vertical().at(b.chainage_end_m).z_m,
                  gen.route.track.vertical().at(b.chainage_end_m).z_m, 2.0);
  }
}

TEST(BlockRoute, UnbuildableBlocksNameTheirIndex) {
  RouteOptions opt;
  std::vector<BlockSpec> blocks(2);
  blocks[0].length_m = 100.0;
  blocks[1] = {BlockType::kCurve, 50.0, 0.0, Turn::kLeft, -1.0, -1.0, 0.0};
  try {
    buildBlockRoute(blocks, opt);
    FAIL() << "a curve without radius was laid out";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("route.blocks[1]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(buildBlockRoute({}, opt), ConfigError);
}

class WaypointFile : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& text) {
    path_ = std::filesystem::temp_directory_path() /
            ("trainsim_wp_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv");
    std::ofstream(path_) << text;
    return path_;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::filesystem::path path_;
  GeodeticAnchor anchor_{{43.7228, 10.3966, 50.0}};
};

TEST_F(WaypointFile, FitsTheElementChainThroughThePoints) {
  const auto f = write(
      "n_m,e_m,d_m,block\n0,0,0,\n0,3000,-10,station\n2000,5000,-12,\n2000,9000,-20,tunnel\n"
      "1000,12000,-5,\n");
  const DesignedRoute d = importWaypoints(f, anchor_, {}, RouteOptions{});
  EXPECT_TRUE(checkDesign(d.route, RouteOptions{}.rules).empty());
  // The straights lie on the legs: the start and end are the first and last waypoints.
  const Track& t = d.route.track;
  EXPECT_LT((t.atChainage(0).position.head<2>() - Eigen::Vector2d(0, 0)).norm(), 1e-9);
  EXPECT_LT((t.atChainage(t.length()).position.head<2>() - Eigen::Vector2d(12000, 1000)).norm(),
            1e-6);
  EXPECT_NEAR(t.atChainage(t.length()).position.z(), 5.0, 1e-6);
  int stations = 0, tunnels = 0, curves = 0;
  for (const Block& b : d.route.blocks) {
    stations += b.type == BlockType::kStation;
    tunnels += b.type == BlockType::kTunnel;
    curves += b.type == BlockType::kCurve;
  }
  EXPECT_EQ(stations, 1);
  EXPECT_EQ(tunnels, 1);
  EXPECT_EQ(curves, 3);
}

TEST_F(WaypointFile, LatitudeLongitudeGoThroughTheAnchor) {
  const GeodeticPoint a = anchor_.fromEnu({2000, 0, 0});
  const GeodeticPoint b = anchor_.fromEnu({4000, 1500, 0});
  const auto f = write(fmt::format(
      "latitude_deg,longitude_deg,height_m\n{:.12f},{:.12f},50\n"
      "{:.12f},{:.12f},60\n{:.12f},{:.12f},62\n",
      43.7228, 10.3966, a.latitude_deg, a.longitude_deg, b.latitude_deg, b.longitude_deg));
  const DesignedRoute d = importWaypoints(f, anchor_, {}, RouteOptions{});
  // Designed in the anchor's azimuthal equidistant projection scaled to the rail's mean
  // height (57.3 m): the plane track ends at b's projection, 12 m above the anchor.
  const Eigen::Vector3d plane_end = d.route.track.atChainage(d.route.track.length()).position;
  const double scale = 1.0 + (50.0 + 60.0 + 62.0) / 3.0 / anchor_.gaussianRadius();
  const Eigen::Vector2d b_plane =
      scale * anchor_.toAzimuthalEquidistant(b.latitude_deg, b.longitude_deg);
  EXPECT_LT((plane_end.head<2>() - b_plane).norm(), 1e-6);
  EXPECT_NEAR(plane_end.z(), 12.0, 1e-6);
  // Laid on the ellipsoid (as every plan does) it keeps the height exactly; horizontally it
  // passes b within (Δh/R)·d + d³/R²: 5 m of height off the mean over 4.3 km, and the
  // projection's distortion off the radial lines, 1.6 mm at 4 km.
  Track placed = d.route.track;
  placed.placeOnEarth(anchor_.origin());
  const GeodeticPoint end = anchor_.fromEnu(placed.atChainage(placed.length()).position);
  EXPECT_NEAR(end.height_m, 62.0, 1e-6);
  const Eigen::Vector3d gap = anchor_.toEnu({end.latitude_deg, end.longitude_deg, 62.0}) -
                              anchor_.toEnu({b.latitude_deg, b.longitude_deg, 62.0});
  EXPECT_LT(gap.norm(), 6e-3);
}

// Waypoints with a curve that is far too tight for 160 km/h and a 30 permille grade: the
// report names those rules at the chainages where the track passes those waypoints.
TEST_F(WaypointFile, BadFileReportsViolationsAtTheRightChainages) {
  const auto f = write(
      "n_m,e_m,d_m,radius_m\n0,0,0,\n0,2000,0,300\n1500,2600,0,\n1500,5000,-72,\n"
      "1500,7000,-72,\n");
  RouteOptions o;
  const DesignedRoute d = importWaypoints(f, anchor_, {}, o);
  const std::vector<Violation> v = checkDesign(d.route, o.rules);
  const Track& t = d.route.track;
  auto nearest = [&](const Eigen::Vector2d& p) {
    double best = 1e300, at = 0;
    for (double s = 0; s <= t.length(); s += 0.25) {
      const double dist = (t.atChainage(s).position.head<2>() - p).norm();
      if (dist < best) {
        best = dist;
        at = s;
      }
    }
    return at;
  };
  bool radius = false, grade = false;
  for (const Violation& x : v) {
    if (x.rule == "min_radius") {
      radius = true;
      EXPECT_NEAR(x.value, 300.0, 1e-6);
      // The arc is centred on the chainage nearest to the waypoint (2000 E, 0 N).
      EXPECT_NEAR(0.5 * (x.chainage_begin_m + x.chainage_end_m), nearest({2000, 0}), 1.0);
    }
    if (x.rule == "gradient") {
      // The 30 permille grade element lies between the two waypoints; the vertical curves at
      // either end reach 30 permille too and stick out by their tangent length (< 300 m).
      // Grades run between the points of the track nearest to the waypoints (the curve at the
      // first one cuts its corner, so the grade is a little steeper than 72 m / 2400 m).
      const double c3 = nearest({2600, 1500}), c4 = nearest({5000, 1500});
      EXPECT_NEAR(x.value, 72.0 / (c4 - c3) * 1e3, 0.05);
      EXPECT_GE(x.chainage_begin_m, c3 - 300.0);
      EXPECT_LE(x.chainage_end_m, c4 + 300.0);
      if (x.chainage_begin_m >= c3 - 1.0 && x.chainage_end_m <= c4 + 1.0)
        grade = true;
    }
  }
  EXPECT_TRUE(radius);
  EXPECT_TRUE(grade);
}

TEST_F(WaypointFile, MalformedFilesNameTheLine) {
  auto expectError = [&](const std::string& text, const std::string& needle) {
    const auto f = write(text);
    try {
      importWaypoints(f, anchor_, {}, RouteOptions{});
      ADD_FAILURE() << "no error for: " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectError("x,y\n1,2\n", "the header needs the columns");
  expectError("n_m,e_m,d_m\n0,0,0\n0,abc,0\n", ":3: column 'e_m': 'abc' is not a number");
  expectError("n_m,e_m,d_m\n0,0,0\n", "at least two waypoints");
  expectError("n_m,e_m,d_m\n0,0,0\n0,0,1\n", "repeats the one on line 2");
  expectError("n_m,e_m,d_m,block\n0,0,0,viaduct\n0,10,0,\n", "'viaduct' is not one of");
  // A given radius that takes the whole next leg leaves no room for the next curve.
  expectError("n_m,e_m,d_m,radius_m\n0,0,0,\n0,1000,0,2000\n300,1100,0,\n300,2000,0,\n",
              "does not fit between its neighbours");
  try {
    importWaypoints("/nonexistent/route.csv", anchor_, {}, RouteOptions{});
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/route.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace trainsim::track
