// Train kinematics: closed-form rates against analytic values, finite-difference consistency
// of the sampled motion, and the limits of the speed profile.
#include <gtest/gtest.h>

#include <cmath>

#include "trainsim/core/error.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace trainsim::track {
namespace {

constexpr double kV = 30.0;  // m/s

Track flatTrack(std::vector<HorizontalElement> elements, CantProfile cant = {},
                CantRotation rotation = CantRotation::kInnerRail) {
  HorizontalAlignment h({100.0, -50.0}, 0.3, std::move(elements));
  const double len = h.length();
  return Track(std::move(h), VerticalProfile(len + 1.0, 5.0), std::move(cant), rotation);
}

MotionState cruise(double u) {
  return {u, kV, 0.0, 0.0};
}

TEST(Kinematics, ArcYawRateAndLateralAcceleration) {
  for (double radius : {-350.0, 800.0, 5000.0}) {
    const double cant = radius > 0 ? -0.1 : 0.1;  // banked into the curve
    const Track t = flatTrack({HorizontalElement::arc(600, radius)},
                              CantProfile({{600, cant, cant, RampShape::kLinear}}));
    const BodyState b = bodyState(t, {17.5}, cruise(300));
    const double r = std::abs(radius);
    EXPECT_NEAR(b.euler_rate.z(), kV / radius, 1e-6 * kV / r);
    EXPECT_NEAR(b.w_body.norm(), kV / r, 1e-6 * kV / r);
    // The pivots run on the centreline: |a| = v²/R, pointing at the centre.
    const Eigen::Vector3d a = t.atDistance(300).d2 * kV * kV;
    EXPECT_NEAR(b.front.z(), t.atDistance(300).position.z(), 1e-12);
    const Eigen::Vector3d front_a = 2.0 * b.origin_a - (t.atDistance(300 - 17.5).d2 * kV * kV);
    EXPECT_NEAR(front_a.norm(), kV * kV / r, 1e-6 * kV * kV / r);
    EXPECT_NEAR(a.norm(), kV * kV / r, 1e-6 * kV * kV / r);
    // A body point at the centre of the pivots' chord circles at radius sqrt(R² − (a/2)²).
    const double rc = std::sqrt(r * r - 17.5 * 17.5 / 4);
    EXPECT_NEAR(b.origin_a.norm(), kV * kV / (r * r) * rc, 1e-6 * kV * kV / r);
    EXPECT_NEAR(b.alpha_body.norm(), 0.0, 1e-12);
  }
}

TEST(Kinematics, ClothoidCurvatureLinearHeadingQuadratic) {
  const double R = 600, L = 120;
  const Track t = flatTrack({HorizontalElement::transition(L, 0, 1 / R)});
  for (double s = 0; s <= L; s += 7.5) {
    const TrackPoint p = t.atChainage(s);
    EXPECT_NEAR(p.curvature_1_m, s / (R * L), 1e-15);
    EXPECT_NEAR(p.heading_rad - 0.3, s * s / (2 * R * L), 1e-14);
  }
}

TEST(Kinematics, VerticalCurvePitchRate) {
  const double rv = 9000.0;
  const VerticalProfile v = VerticalProfile::fromPvis({{0, 0, 0}, {1000, -8, rv}, {2000, 4, 0}});
  const Track t(HorizontalAlignment({0, 0}, 0, {HorizontalElement::straight(2000)}), v, {});
  const double u = v.at(1000).distance_m;
  const BodyState b = bodyState(t, {17.5}, cruise(u));
  // Both pivots on the same vertical circle: the chord pitches at exactly v/R_v (sag: up).
  EXPECT_NEAR(b.euler_rate.y(), kV / rv, 1e-9 * kV / rv);
  EXPECT_NEAR(b.w_body.y(), -kV / rv, 1e-9 * kV / rv);  // nose up is −y rotation (FLU)
}

TEST(Kinematics, RollRateInLinearCantRamp) {
  const double R = 900, L = 150, D = 0.12;
  for (CantRotation rot : {CantRotation::kInnerRail, CantRotation::kCentre}) {
    const Track t =
        flatTrack({HorizontalElement::straight(100), HorizontalElement::transition(L, 0, -1 / R),
                   HorizontalElement::arc(300, -R)},
                  CantProfile({{100, 0, 0, RampShape::kLinear},
                               {L, 0, D, RampShape::kLinear},
                               {300, D, D, RampShape::kLinear}}),
                  rot);
    for (double u = 140; u < 250; u += 13) {
      // φ_i = asin(D(s_i)/b), D(s) = D (s − 100)/L on the ramp: φ̇_i = (D/L) v / sqrt(b² − D_i²).
      auto rate = [&](double s) {
        if (s < 100 || s > 100 + L)
          return 0.0;
        const double d = D * (s - 100) / L;
        return D / L * kV / std::sqrt(1.5 * 1.5 - d * d);
      };
      // Wheelbase 0: the mean of the two pivots; 2.5 m: the mean of the four wheelsets.
      for (const double w : {0.0, 2.5}) {
        const BodyState b = bodyState(t, {17.5, w}, cruise(u));
        const double h = w / 2;
        const double expected =
            w == 0.0 ? 0.5 * (rate(u) + rate(u - 17.5))
                     : 0.25 * (rate(u - h) + rate(u + h) + rate(u - 17.5 - h) + rate(u - 17.5 + h));
        EXPECT_NEAR(b.euler_rate.x(), expected, 1e-12) << "wheelbase " << w << ", u " << u;
        // Level track without lift: the body-axis roll rate is the Euler roll rate.
        if (rot == CantRotation::kCentre) {
          EXPECT_NEAR(b.w_body.x(), expected, 1e-12);
        }
      }
    }
  }
}

// Central differences of a smooth quantity converge at second order: halving the step divides
// the error by four, as long as the error is above rounding noise.
template <typename Exact, typename Fd>
void expectSecondOrder(const Exact& exact, const Fd& fd, double h, double noise) {
  const double e1 = (fd(h) - exact()).norm();
  const double e2 = (fd(h / 2) - exact()).norm();
  if (e1 < noise)
    return;
  EXPECT_GT(e1 / e2, 3.0) << "e(h) " << e1 << " e(h/2) " << e2;
  EXPECT_LT(e1 / e2, 5.2) << "e(h) " << e1 << " e(h/2) " << e2;
}

struct Generated {
  DesignedRoute route;
  MotionProfile motion;
};

Generated generated(std::uint64_t seed, TransitionShape shape) {
  RouteGeneratorParams p;
  p.length_m = 6000;
  RouteOptions o;
  o.transition_shape = shape;
  Generated g{generateRoute(p, o, seed), {}};
  const double len = g.route.route.track.distanceLength();
  g.motion = planMotion(g.route.route, g.route.stops, {}, {}, 17.5, len - 1.0);
  return g;
}

TEST(Kinematics, FiniteDifferencesMatchClosedFormsAtSecondOrder) {
  const Generated g = generated(3, TransitionShape::kBloss);
  const Track& t = g.route.route.track;
  const VehicleGeometry geo{17.5};
  const Eigen::Vector3d r(4.0, 0.6, 3.2);  // a sensor on the roof, off-centre
  auto at = [&](double time) { return bodyState(t, geo, g.motion.at(time)); };
  int checked = 0;
  for (double time = 5.0; time < g.motion.duration() - 5.0; time += 7.3) {
    // Skip instants next to a change of jerk (the motion is only C² there) and where either
    // pivot is within reach of a joint of the horizontal, vertical or cant profile (where
    // curvature rate, vertical curvature or roll acceleration step).
    bool near_joint = false;
    for (const MotionSegment& s : g.motion.segments())
      near_joint |= std::abs(s.t0_s - time) < 0.05;
    const MotionState m = g.motion.at(time);
    for (double u : {m.u_m, m.u_m - geo.bogie_spacing_m}) {
      const double s = t.vertical().chainageAt(u);
      const double reach = 0.05 * m.v_m_s + 1.0;
      for (std::size_t i = 0; i <= t.horizontal().elements().size(); ++i)
        near_joint |= std::abs(t.horizontal().elementStart(i) - s) < reach;
      for (std::size_t i = 0; i <= t.vertical().elements().size(); ++i)
        near_joint |= std::abs(t.vertical().elementStart(i) - s) < reach;
      for (std::size_t i = 0; i <= t.cant().elements().size(); ++i)
        near_joint |= std::abs(t.cant().elementStart(i) - s) < reach;
    }
    if (near_joint)
      continue;
    const BodyState b = at(time);
    const double h = 0.01;
    // Central difference over ±k of a vector quantity of the body state.
    auto central = [&](auto quantity) {
      return [&, quantity](double k) {
        return Eigen::Vector3d((quantity(at(time + k)) - quantity(at(time - k))) / (2 * k));
      };
    };
    expectSecondOrder([&] { return b.pointVelocity(r); },
                      central([&](const BodyState& x) { return x.pointPosition(r); }), h, 1e-9);
    expectSecondOrder([&] { return b.pointAcceleration(r); },
                      central([&](const BodyState& x) { return x.pointVelocity(r); }), h, 1e-9);
    expectSecondOrder([&] { return b.alpha_body; },
                      central([](const BodyState& x) { return x.w_body; }), h, 1e-11);
    // Angular velocity against the rotation increment over ±h.
    expectSecondOrder([&] { return b.w_body; },
                      [&](double k) {
                        const Eigen::AngleAxisd d(at(time - k).r_world_body.transpose() *
                                                  at(time + k).r_world_body);
                        // The increment's axis is in the body frame at the mid time, to O(h²).
                        return Eigen::Vector3d(d.axis() * d.angle() / (2 * k));
                      },
                      h, 1e-11);
    ++checked;
  }
  EXPECT_GT(checked, 15);
}

// The bound the sampled velocity must meet at sample period T: the central difference of the
// position differs from the velocity by at most T²/6 max|d³P/dt³|, and for a point on the track
// d³P/dt³ = P''' u̇³ + 3 P'' u̇ ü + P' u⃛ with |P'''| ≤ |κ'| + κ² (+ vertical terms).
TEST(Kinematics, SampledVelocityWithinDerivedBound) {
  const Generated g = generated(11, TransitionShape::kClothoid);
  const Track& t = g.route.route.track;
  const MotionLimits lim;
  double kmax = 0, kdot = 0;
  for (const HorizontalElement& e : t.horizontal().elements()) {
    kmax = std::max({kmax, std::abs(e.curvature_start_1_m), std::abs(e.curvature_end_1_m)});
    if (e.type == HorizontalElement::Type::kTransition)
      kdot = std::max(kdot, std::abs(e.curvature_end_1_m - e.curvature_start_1_m) / e.length_m);
  }
  double kv = 0;
  for (const VerticalElement& e : t.vertical().elements())
    kv = std::max(kv, std::abs(e.curvature_1_m));
  const double vmax = RouteOptions{}.rules.design_speed_m_s;
  const double k_all = kmax + kv;
  const double m3 = (kdot + k_all * k_all) * vmax * vmax * vmax +
                    3 * k_all * vmax * std::max(lim.accel_m_s2, lim.brake_m_s2) + lim.jerk_m_s3;
  const double T = 0.01;
  const double bound = T * T / 6 * m3 + 1e-9;
  double worst = 0;
  for (double time = T; time < g.motion.duration() - T; time += 0.37) {
    const MotionState m = g.motion.at(time);
    const Eigen::Vector3d v = t.atDistance(m.u_m).d1 * m.v_m_s;
    const Eigen::Vector3d fd = (t.atDistance(g.motion.at(time + T).u_m).position -
                                t.atDistance(g.motion.at(time - T).u_m).position) /
                               (2 * T);
    worst = std::max(worst, (fd - v).norm());
  }
  EXPECT_LT(worst, bound) << "bound " << bound;
  EXPECT_GT(worst, 0.0);
}

TEST(Motion, SpeedAccelerationAndJerkStayWithinTheirLimits) {
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const Generated g = generated(seed, TransitionShape::kClothoid);
    const MotionLimits lim;
    const double len = g.route.route.track.distanceLength();
    int stops = 0;
    double stopped_since = -1;
    for (double time = 0; time <= g.motion.duration(); time += 0.05) {
      const MotionState m = g.motion.at(time);
      ASSERT_LE(m.v_m_s, g.motion.limit().at(m.u_m) + 1e-9) << "seed " << seed << " t " << time;
      ASSERT_GE(m.v_m_s, 0.0);
      ASSERT_LE(m.a_m_s2, lim.accel_m_s2 + 1e-12);
      ASSERT_GE(m.a_m_s2, -lim.brake_m_s2 - 1e-12);
      ASSERT_LE(std::abs(m.jerk_m_s3), lim.jerk_m_s3 + 1e-12);
      if (m.v_m_s == 0.0 && m.u_m > 20 && m.u_m < len - 2) {
        if (stopped_since < 0) {
          ++stops;
          stopped_since = time;
        }
      } else {
        stopped_since = -1;
      }
    }
    // The limit in force covers the whole train: check against every block under it.
    for (double time = 0; time <= g.motion.duration(); time += 0.5) {
      const MotionState m = g.motion.at(time);
      const VerticalProfile& vp = g.route.route.track.vertical();
      for (double back = 0; back <= lim.train_length_m; back += 5) {
        const double s = vp.chainageAt(std::max(0.0, m.u_m - back));
        ASSERT_LE(m.v_m_s, speedLimitAt(g.route.route, s) + 1e-9);
      }
    }
    EXPECT_EQ(stops, static_cast<int>(g.route.stops.size())) << "seed " << seed;
    // The run ends at rest at the end of the track.
    const MotionState end = g.motion.at(g.motion.duration());
    EXPECT_NEAR(end.u_m, len - 1.0, 1e-6);
    EXPECT_NEAR(end.v_m_s, 0.0, 1e-9);
  }
}

TEST(Motion, DynamicsLimitAccelerationOnClimbs) {
  RouteGeneratorParams p;
  p.length_m = 8000;
  p.grade_max = 0.0125;
  const DesignedRoute d = generateRoute(p, RouteOptions{}, 5);
  TrainDynamics dyn;
  dyn.enabled = true;
  const double len = d.route.track.distanceLength();
  const MotionProfile m = planMotion(d.route, d.stops, {}, dyn, 17.5, len - 1);
  const MotionProfile free = planMotion(d.route, d.stops, {}, {}, 17.5, len - 1);
  EXPECT_GT(m.duration(), free.duration());
  for (double time = 0; time < m.duration(); time += 0.1) {
    const MotionState s = m.at(time);
    if (s.a_m_s2 <= 0)
      continue;
    const double sin_grade = std::sin(d.route.track.atDistance(s.u_m).pitch_rad);
    // Planned acceleration never exceeds what traction leaves after resistance and grade
    // (the plan uses each section's worst grade and speed, so it is conservative).
    ASSERT_LE(s.a_m_s2, dyn.availableAccel(s.v_m_s, sin_grade) + 1e-9) << "t " << time;
  }
}

TEST(Motion, TractionTooWeakForTheGradeIsBadInput) {
  RouteGeneratorParams p;
  p.length_m = 8000;
  p.grade_max = 0.0125;
  const DesignedRoute d = generateRoute(p, RouteOptions{}, 5);
  TrainDynamics dyn;
  dyn.enabled = true;
  dyn.max_traction_n = 20e3;  // a 260 t train on 12.5 permille needs about 32 kN
  EXPECT_THROW(planMotion(d.route, d.stops, {}, dyn, 17.5, d.route.track.distanceLength() - 1),
               ConfigError);
}

}  // namespace
}  // namespace trainsim::track
