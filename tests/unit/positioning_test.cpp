// GNSS, odometer and balise physics on their module alone (no scenario, no dataset).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "trainsim/positioning/balise.hpp"
#include "trainsim/positioning/gnss.hpp"
#include "trainsim/positioning/odometer.hpp"

namespace trainsim::positioning {
namespace {

constexpr TimeNs kSecond = 1'000'000'000;

TEST(GnssErrorModel, GaussMarkovHasItsSigmaAndCorrelationTime) {
  GnssErrorSpec spec;
  spec.white_sigma_m = 0.0;
  spec.correlation_time_s = 10.0;
  GnssErrorModel model(spec, kSecond, RandomStream(3, "gnss"));
  const int n = 200'000;
  double sum2_e = 0, sum2_u = 0, lag1 = 0, prev = 0;
  for (int k = 0; k < n; ++k) {
    const GnssErrors e = model.step(static_cast<std::uint64_t>(k));
    sum2_e += e.position_m.x() * e.position_m.x();
    sum2_u += e.position_m.z() * e.position_m.z();
    if (k > 0)
      lag1 += e.position_m.x() * prev;
    prev = e.position_m.x();
  }
  // Stationary from the first reading: σ per axis, lag-1 correlation φ = exp(−T/τ).
  EXPECT_NEAR(std::sqrt(sum2_e / n), 1.5, 1.5 * 0.03);
  EXPECT_NEAR(std::sqrt(sum2_u / n), 3.0, 3.0 * 0.03);
  EXPECT_NEAR(lag1 / sum2_e, std::exp(-0.1), 0.01);
}

TEST(GnssErrorModel, WhiteNoiseAddsInQuadrature) {
  GnssErrorSpec spec;
  spec.horizontal_sigma_m = 0.0;
  spec.vertical_sigma_m = 0.0;
  spec.velocity_gm_sigma_m_s = 0.0;
  spec.white_sigma_m = 0.4;
  spec.velocity_sigma_m_s = 0.1;
  GnssErrorModel model(spec, kSecond, RandomStream(4, "gnss"));
  double p2 = 0, v2 = 0, lag = 0, prev = 0;
  const int n = 100'000;
  for (int k = 0; k < n; ++k) {
    const GnssErrors e = model.step(static_cast<std::uint64_t>(k));
    p2 += e.position_m.squaredNorm();
    v2 += e.velocity_m_s.squaredNorm();
    lag += e.position_m.y() * prev;
    prev = e.position_m.y();
  }
  EXPECT_NEAR(std::sqrt(p2 / (3 * n)), 0.4, 0.4 * 0.02);
  EXPECT_NEAR(std::sqrt(v2 / (3 * n)), 0.1, 0.1 * 0.02);
  EXPECT_NEAR(lag / n, 0.0, 0.01);  // uncorrelated
}

TEST(GnssErrorModel, RestoredStateContinuesBitForBit) {
  const GnssErrorSpec spec;
  GnssErrorModel a(spec, kSecond, RandomStream(5, "gnss"));
  for (int k = 0; k < 50; ++k)
    a.step(static_cast<std::uint64_t>(k));
  GnssErrorModel b(spec, kSecond, RandomStream(5, "gnss"));
  b.restore(a.state());
  for (int k = 50; k < 80; ++k)
    EXPECT_EQ(a.step(static_cast<std::uint64_t>(k)).position_m,
              b.step(static_cast<std::uint64_t>(k)).position_m);
}

// A tunnel over [100, 200] m, passed at 7.3 m/s: the antenna leaves it at t = 200 / 7.3 s. At
// any sample rate the first fix comes at the first sample at least 5 s after that, timed from
// the exit itself (not from the last sample inside).
TEST(GnssVisibility, FixReturnsTheReacquisitionDelayAfterTheAntennaLeavesTheTunnel) {
  const GnssVisibility visibility({{100.0, 200.0}, {900.0, 950.0}}, 5 * kSecond);
  const auto chainage = [](TimeNs t) { return 7.3 * toSeconds(std::max<TimeNs>(t, 0)); };
  const double exit_s = 200.0 / 7.3;
  EXPECT_TRUE(visibility.inTunnel(100.0));
  EXPECT_TRUE(visibility.inTunnel(200.0));
  EXPECT_FALSE(visibility.inTunnel(200.001));
  EXPECT_FALSE(visibility.inTunnel(500.0));
  for (const TimeNs period : {kSecond, kSecond / 10, kSecond / 100, kSecond / 1000}) {
    TimeNs first_fix = -1;
    for (TimeNs t = 0; t < 60 * kSecond; t += period) {
      const double c = chainage(t);
      const bool fix = visibility.fix(t, chainage);
      if (c < 100.0) {
        ASSERT_TRUE(fix) << t;
      } else if (c <= 200.0) {
        ASSERT_FALSE(fix) << "fix inside the tunnel at " << t;
      } else if (first_fix < 0 && fix) {
        first_fix = t;
      }
    }
    ASSERT_GE(first_fix, 0);
    EXPECT_GE(toSeconds(first_fix), exit_s + 5.0) << period;
    EXPECT_LT(toSeconds(first_fix - period), exit_s + 5.0 + 1e-9) << period;
  }
}

TEST(GnssVisibility, NoTunnelsOrNoDelayMeansAFixEverywhereOutside) {
  const auto chainage = [](TimeNs t) { return 10.0 * toSeconds(t); };
  EXPECT_TRUE(GnssVisibility({}, 5 * kSecond).fix(3 * kSecond, chainage));
  const GnssVisibility no_delay({{10.0, 20.0}}, 0);
  EXPECT_FALSE(no_delay.fix(kSecond + kSecond / 2, chainage));
  EXPECT_TRUE(no_delay.fix(2 * kSecond + 1, chainage));
}

OdometerSpec noSlip(double scale_error) {
  OdometerSpec spec;
  spec.scale_error = scale_error;
  spec.slip.enabled = false;
  return spec;
}

TEST(OdometerModel, CountsWholePulsesOfTheScaledDistance) {
  const OdometerSpec spec = noSlip(0.01);
  OdometerModel model(spec, kSecond / 100, RandomStream(1, "odo"));
  const double pulse = std::numbers::pi * 0.92 / 200;
  EXPECT_DOUBLE_EQ(spec.pulseLength_m(), pulse);
  for (int k = 0; k < 1000; ++k) {
    const double s = 0.37 * k;  // 37 m/s
    const OdometerReading r =
        model.step(static_cast<std::uint64_t>(k), k * kSecond / 100, 100 + s, 0);
    ASSERT_EQ(r.pulses, static_cast<std::int64_t>(std::floor(1.01 * s / pulse))) << k;
    ASSERT_DOUBLE_EQ(r.distance_m, static_cast<double>(r.pulses) * pulse);
    ASSERT_EQ(r.slip, 0);
    if (k > 0) {
      ASSERT_NEAR(r.speed_m_s, 1.01 * 37.0, pulse / 0.01 + 1e-9);
    }
  }
}

TEST(OdometerModel, SlipOnlyUnderTractionAndSlideOnlyUnderBraking) {
  OdometerSpec spec = noSlip(0.0);
  spec.slip.enabled = true;
  spec.slip.rate_per_s = 5.0;
  OdometerModel model(spec, kSecond / 100, RandomStream(2, "odo"));
  int slips = 0, slides = 0;
  double u = 0;
  for (int k = 0; k < 30'000; ++k) {
    // Phases of 10 s: coasting, accelerating hard, coasting, braking hard.
    const int phase = (k / 1000) % 4;
    const double a = phase == 1 ? 0.8 : phase == 3 ? -0.8 : 0.0;
    u += 0.2;
    const OdometerReading r = model.step(static_cast<std::uint64_t>(k), k * kSecond / 100, u, a);
    slips += r.slip == 1;
    slides += r.slip == -1;
    // An episode lasts at most 4 s past the end of its phase.
    if (phase == 0 && k % 1000 >= 400) {
      ASSERT_EQ(r.slip, 0) << k;
    }
    if (r.slip == 1) {
      ASSERT_TRUE(phase == 1 || phase == 2) << k;
    }
    if (r.slip == -1) {
      ASSERT_TRUE(phase == 3 || phase == 0) << k;
    }
  }
  EXPECT_GT(slips, 0);
  EXPECT_GT(slides, 0);
}

TEST(Balises, PlacedEveryGroupSpacingPlusBeforeStations) {
  BalisePlacement p;
  const std::vector<double> stations = {2500.0, 30.0};
  const std::vector<Balise> b = placeBalises(p, 3210.0, stations);
  // Groups at 200, 1200, 2200, 3200 (the last one does not fit: 3206 > 3210 is false) and
  // 2450 before the station at 2500; none before the station at 30 m.
  const std::vector<double> groups = {200, 1200, 2200, 2450, 3200};
  ASSERT_EQ(b.size(), 2 * groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g) {
    EXPECT_EQ(b[2 * g].group, static_cast<int>(g));
    EXPECT_DOUBLE_EQ(b[2 * g].u_m, groups[g]);
    EXPECT_DOUBLE_EQ(b[2 * g + 1].u_m, groups[g] + 3.0);
    EXPECT_EQ(b[2 * g + 1].index, 1);
  }
}

TEST(Balises, PassageTimeIsExactForConstantAcceleration) {
  // u(t) = u0 + v0 t + a t²/2 is a cubic Hermite interpolant's own case.
  const double u0 = 100, v0 = 12, a = -0.7;
  const AntennaState s0{0, u0, v0};
  const AntennaState s1{kSecond / 10, u0 + v0 * 0.1 + a * 0.005, v0 + a * 0.1};
  const double target = u0 + 0.6;
  const double t = (-v0 + std::sqrt(v0 * v0 + 2 * a * (target - u0))) / a;
  EXPECT_NEAR(static_cast<double>(passageTime(s0, s1, target)), t * 1e9, 1.0);
}

TEST(Balises, DetectorReadsEachBaliseOnceInOrderAndResumes) {
  BalisePlacement p;
  p.station_approach_m = 0;
  std::vector<Balise> balises = placeBalises(p, 10'000, {});
  BaliseDetector a(balises, 0.0, RandomStream(1, "b")), b(balises, 0.0, RandomStream(1, "b"));
  std::vector<double> read;
  const double v = 25.0, u_start = 1000.0;  // balises before 1000 m are behind the antenna
  for (int k = 0; k <= 3000; ++k) {
    const AntennaState now{k * kSecond / 10, u_start + v * 0.1 * k, v};
    const std::vector<BaliseEvent> events = a.step(now);
    for (const BaliseEvent& e : events) {
      read.push_back(e.balise->u_m);
      // Constant speed: the exact passage time.
      EXPECT_NEAR(static_cast<double>(e.t), (e.balise->u_m - u_start) / v * 1e9, 1.0);
    }
    if (k == 1500)
      b.restore(a.state());  // a reader resumed from a checkpoint reads the same events
    if (k > 1500) {
      const std::vector<BaliseEvent> again = b.step(now);
      ASSERT_EQ(again.size(), events.size()) << k;
      for (std::size_t i = 0; i < events.size(); ++i)
        EXPECT_EQ(again[i].t, events[i].t);
    }
  }
  // 1200, 1203, …, 8200, 8203: 8 groups of 2 between 1000 m and 8500 m.
  ASSERT_EQ(read.size(), 16u);
  EXPECT_DOUBLE_EQ(read.front(), 1200.0);
  EXPECT_DOUBLE_EQ(read.back(), 8203.0);
  for (std::size_t i = 1; i < read.size(); ++i)
    EXPECT_LT(read[i - 1], read[i]);
}

}  // namespace
}  // namespace trainsim::positioning
