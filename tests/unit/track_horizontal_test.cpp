// Horizontal alignment against closed forms: arcs (circle geometry), clothoids (heading
// s²/(2RL) and the Fresnel power series written here), Bloss curves, continuity at joints, and
// a 1000 km chain against an independent re-integration.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support/fresnel_series.hpp"
#include "../support/simpson_chain.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/track/horizontal.hpp"

namespace trainsim::track {
namespace {

using E = HorizontalElement;

TEST(HorizontalAlignment, ArcFollowsItsCircle) {
  const double r = 600.0, th0 = 0.4;
  const HorizontalAlignment a({100.0, -50.0}, th0, {E::arc(500.0, r)});
  // Left-hand arc: centre on the left of the start heading.
  const Eigen::Vector2d centre =
      Eigen::Vector2d(100.0, -50.0) + r * Eigen::Vector2d(-std::sin(th0), std::cos(th0));
  for (double s : {0.0, 1e-7, 0.5, 123.4, 499.999, 500.0}) {
    const HorizontalState st = a.at(s);
    EXPECT_NEAR((st.position_m - centre).norm(), r, 1e-9) << s;
    EXPECT_NEAR(st.heading_rad, th0 + s / r, 1e-15);
    EXPECT_DOUBLE_EQ(st.curvature_1_m, 1.0 / r);
    const Eigen::Vector2d expected =
        centre + r * Eigen::Vector2d(std::sin(th0 + s / r), -std::cos(th0 + s / r));
    EXPECT_NEAR((st.position_m - expected).norm(), 0.0, 1e-9) << s;
  }
  const HorizontalAlignment right({0, 0}, 0.0, {E::arc(100.0, -250.0)});
  EXPECT_LT(right.at(100.0).position_m.y(), 0.0);  // negative radius turns right
}

using testing::clothoidFresnelSeries;

TEST(HorizontalAlignment, ClothoidHasLinearCurvatureAndQuadraticHeading) {
  const double r = 1500.0, l = 110.0;
  const HorizontalAlignment a({0, 0}, 0.0, {E::transition(l, 0.0, 1.0 / r)});
  for (double s : {0.0, 10.0, 55.0, 109.0, 110.0}) {
    const HorizontalState st = a.at(s);
    EXPECT_NEAR(st.curvature_1_m, s / (r * l), 1e-18);
    EXPECT_NEAR(st.heading_rad, s * s / (2 * r * l), 1e-15);
    EXPECT_DOUBLE_EQ(st.curvature_rate_1_m2, 1.0 / (r * l));
    EXPECT_LT((st.position_m - clothoidFresnelSeries(s, r * l)).norm(), 1e-9) << s;
  }
  // Reference-book end offset Y_L ≈ L²/(6R) − L⁴/(336R³); the first omitted term,
  // L⁶/(42240R⁵) ≈ 5.5e-9 m here, bounds the difference.
  EXPECT_NEAR(a.at(l).position_m.y(), l * l / (6 * r) - std::pow(l, 4) / (336 * std::pow(r, 3)),
              std::pow(l, 6) / (42240 * std::pow(r, 5)));
}

TEST(HorizontalAlignment, SharpClothoidMatchesFresnelSeries) {
  // A 190 m radius reached over 80 m: heading turns 0.21 rad, where truncated series fail.
  const double r = 190.0, l = 80.0;
  const HorizontalAlignment a({0, 0}, 0.0, {E::transition(l, 0.0, 1.0 / r)});
  EXPECT_LT((a.at(l).position_m - clothoidFresnelSeries(l, r * l)).norm(), 1e-9);
}

TEST(HorizontalAlignment, BlossHasZeroCurvatureRateAtBothEnds) {
  const double r = 1000.0, l = 120.0;
  const E e = E::transition(l, 0.0, 1.0 / r, TransitionShape::kBloss);
  EXPECT_DOUBLE_EQ(e.curvatureRate(0.0), 0.0);
  EXPECT_NEAR(e.curvatureRate(l), 0.0, 1e-20);
  EXPECT_DOUBLE_EQ(e.curvature(l), 1.0 / r);
  EXPECT_NEAR(e.headingChange(l), l / (2 * r), 1e-15);  // same end deflection as a clothoid
  // Heading is the integral of curvature: check with a fine midpoint rule.
  double integral = 0.0;
  const int n = 100000;
  for (int i = 0; i < n; ++i)
    integral += e.curvature((i + 0.5) * l / n) * l / n;
  EXPECT_NEAR(e.headingChange(l), integral, 1e-12);
}

TEST(HorizontalAlignment, PositionAndHeadingAreContinuousAtJoints) {
  const double r = 800.0;
  const HorizontalAlignment a(
      {10, 20}, -1.0,
      {E::straight(200.0), E::transition(90.0, 0.0, 1.0 / r), E::arc(300.0, r),
       E::transition(90.0, 1.0 / r, 0.0), E::straight(100.0),
       E::transition(60.0, 0.0, -1.0 / 400.0, TransitionShape::kBloss), E::arc(50.0, -400.0)});
  for (std::size_t i = 1; i < a.elements().size(); ++i) {
    const double s = a.elementStart(i);
    const HorizontalState before = a.at(std::nextafter(s, 0.0));
    const HorizontalState after = a.at(s);
    EXPECT_LT((before.position_m - after.position_m).norm(), 1e-9) << "joint " << i;
    EXPECT_NEAR(before.heading_rad, after.heading_rad, 1e-12) << "joint " << i;
    EXPECT_NEAR(before.curvature_1_m, after.curvature_1_m, 1e-12) << "joint " << i;
  }
  EXPECT_DOUBLE_EQ(a.length(), 890.0);
}

TEST(HorizontalAlignment, RejectsNonPositiveLengths) {
  EXPECT_THROW(HorizontalAlignment({0, 0}, 0, {E::straight(0.0)}), ConfigError);
  EXPECT_THROW(HorizontalAlignment({0, 0}, 0, {}), ConfigError);
}

TEST(HorizontalAlignment, ThousandKilometresKeepSubMillimetrePrecision) {
  // 2000 repetitions of a 500 m S-bend unit: straight, transitions, arcs left and right.
  std::vector<E> unit = {
      E::straight(120.0),    E::transition(60.0, 0.0, 1.0 / 900.0),
      E::arc(70.0, 900.0),   E::transition(60.0, 1.0 / 900.0, 0.0),
      E::straight(50.0),     E::transition(40.0, 0.0, -1.0 / 1200.0, TransitionShape::kBloss),
      E::arc(60.0, -1200.0), E::transition(40.0, -1.0 / 1200.0, 0.0, TransitionShape::kBloss)};
  std::vector<E> chain;
  for (int i = 0; i < 2000; ++i)
    chain.insert(chain.end(), unit.begin(), unit.end());
  const Eigen::Vector2d start(3.0e5, -2.0e5);
  const HorizontalAlignment a(start, 0.3, chain);
  ASSERT_NEAR(a.length(), 1.0e6, 1e-6);

  // Independent re-integration: Simpson's rule on the closed-form heading with a 0.25 m step,
  // in long double, one element at a time (so that the heading's kinks fall on grid points).
  const testing::ChainEnd ref = testing::simpsonChainEnd(chain, start.x(), start.y(), 0.3L, 0.25);
  const long double x = ref.x, y = ref.y, th = ref.heading;
  const HorizontalState end = a.at(a.length());
  EXPECT_LT(std::hypot(static_cast<double>(x) - end.position_m.x(),
                       static_cast<double>(y) - end.position_m.y()),
            1e-3);
  EXPECT_NEAR(end.heading_rad, static_cast<double>(th), 1e-9);
}

}  // namespace
}  // namespace trainsim::track
