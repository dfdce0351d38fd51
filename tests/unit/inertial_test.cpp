// Inertial truth and error models: static gravity and Earth rate, steady curve, strapdown
// closure with an independent integrator, Allan-deviation recovery, rate invariance,
// quantization and saturation.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <numbers>

#include "trainsim/inertial/earth.hpp"
#include "trainsim/inertial/error_model.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace trainsim::inertial {
namespace {

constexpr double kOmega = 7.292115e-5;

// Somigliana normal gravity with the second-order height series (docs/REFERENCES.md R2.5),
// written independently of GeographicLib.
double somigliana(double lat_deg, double h) {
  const double a = 6378137.0, f = 1 / 298.257223563, m = 0.00344978650684;
  const double ge = 9.7803253359, k = 0.00193185265241, e2 = 0.00669437999014;
  const double s2 = std::pow(std::sin(lat_deg * std::numbers::pi / 180), 2);
  const double g0 = ge * (1 + k * s2) / std::sqrt(1 - e2 * s2);
  return g0 * (1 - 2 / a * (1 + f + m - 2 * f * s2) * h + 3 * h * h / (a * a));
}

TEST(Inertial, StaticReadsNormalGravityAndEarthRate) {
  for (double lat : {-60.0, 0.0, 23.5, 43.7228, 52.0, 78.0}) {
    for (double h : {0.0, 50.0, 1200.0}) {
      const Earth earth({lat, 10.0, h});
      const ImuTruth t = imuTruth(earth, {});
      // Level at rest in ENU axes: the accelerometer senses +γ up and nothing east. Above
      // the ellipsoid the normal plumb line curves towards the pole, so a small northward
      // component appears (about 7e-9 m/s² per metre of height at mid latitudes).
      EXPECT_NEAR(t.specific_force.x(), 0.0, 1e-9);
      EXPECT_NEAR(t.specific_force.y(), 0.0, 1e-8 * h + 1e-9);
      EXPECT_NEAR(t.specific_force.z(), somigliana(lat, h), 2e-6) << lat << " " << h;
      const double phi = lat * std::numbers::pi / 180;
      EXPECT_NEAR(t.angular_rate.x(), 0.0, 1e-15);
      EXPECT_NEAR(t.angular_rate.y(), kOmega * std::cos(phi), 1e-12);
      EXPECT_NEAR(t.angular_rate.z(), kOmega * std::sin(phi), 1e-12);
    }
  }
  // A sensor turned 90° about z sees the north rate on its −x axis.
  const Earth earth({45.0, 0.0, 0.0});
  MountKinematics m;
  m.r_world_sensor =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(imuTruth(earth, m).angular_rate.x(), kOmega * std::cos(std::numbers::pi / 4), 1e-12);
}

// On an arc with cant D at speed v (flat Earth, so gravity is exactly vertical): yaw rate v/R,
// track-plane lateral specific force (v²/R) cos φ − g sin φ, normal g cos φ + (v²/R) sin φ.
TEST(Inertial, SteadyCurveLateralAndNormalSpecificForce) {
  using namespace track;
  const double r = 1200, d = 0.12, v = 40.0;
  const Track t(HorizontalAlignment({0, 0}, 0.0, {HorizontalElement::arc(800, -r)}),
                VerticalProfile(801, 0.0), CantProfile({{800, d, d, RampShape::kLinear}}));
  // Pivots 1 mm apart: the body axes are the track-plane axes at the point (the chord of a
  // real bogie spacing turns them by L/2R, which is not what this check is about).
  const BodyState b = bodyState(t, {1e-3, 0.0}, {400, v, 0, 0});
  const Earth earth({45.0, 0.0, 0.0}, false);
  const double g = -earth.gravity({0, 0, 0}).z();
  // The front pivot, on the centreline, in the body's axes.
  MountKinematics m;
  m.r_world_sensor = b.r_world_body;
  m.a_world = t.atDistance(400).d2 * v * v;
  m.w_sensor = b.w_body;
  const ImuTruth truth = imuTruth(earth, m);
  const double phi = std::asin(d / 1.5);
  // Right-hand curve: the centre is on the right (−y), the outer (left) rail is higher.
  const double lateral = v * v / r * std::cos(phi) - g * std::sin(phi);
  EXPECT_NEAR(-truth.specific_force.y(), lateral, 1e-6 * std::abs(lateral));
  const double normal = g * std::cos(phi) + v * v / r * std::sin(phi);
  EXPECT_NEAR(truth.specific_force.z(), normal, 1e-6 * normal);
  EXPECT_NEAR(-b.euler_rate.z(), v / r, 1e-6 * v / r);
}

// Noise-free IMU samples of a generated 10 km route, integrated by a strapdown mechanisation
// written here (Earth-fixed ENU frame, same Earth model: ṗ = v, v̇ = R f + g(p) − 2Ω×v,
// q̇ = ½ q⊗ω − ½ Ω⊗q, classical RK4 over two sample periods), reproduce the trajectory.
// Sampled at 2 kHz the worst position error over the run is 3.6 mm. The samples are
// instantaneous rates, and the specific force steps by v²/R_v where a circular vertical curve
// meets a grade, which a sample-based integrator resolves only to O(h·Δf): 1.7 cm at 1 kHz,
// 5.5 cm at 400 Hz. Increment outputs (Δv, Δθ integrated from the exact trajectory) would
// remove that; see docs/PERFORMANCE.md.
TEST(Inertial, StrapdownClosureOverTenKilometres) {
  using namespace track;
  RouteGeneratorParams p;
  p.length_m = 10000;
  p.station.probability = 0;  // one continuous run
  RouteOptions o;
  o.transition_shape = TransitionShape::kBloss;
  const DesignedRoute d = generateRoute(p, o, 21);
  const MotionProfile motion =
      planMotion(d.route, d.stops, {}, {}, 17.5, d.route.track.distanceLength() - 1.0);
  const Earth earth({43.7228, 10.3966, 50.0});
  const double dt = 0.0005;  // 2 kHz
  const auto n = static_cast<std::int64_t>(motion.duration() / dt);
  struct Sample {
    ImuTruth imu;
    Eigen::Vector3d p, v;
    Eigen::Matrix3d r;
  };
  auto sample = [&](std::int64_t k) {
    const BodyState b = bodyState(d.route.track, {17.5}, motion.at(static_cast<double>(k) * dt));
    MountKinematics m{b.origin, b.origin_v, b.origin_a, b.r_world_body, b.w_body};
    return Sample{imuTruth(earth, m), b.origin, b.origin_v, b.r_world_body};
  };
  const Eigen::Vector3d omega = earth.rate();
  struct State {
    Eigen::Vector3d p, v;
    Eigen::Quaterniond q;
  };
  auto derivative = [&](const State& x, const ImuTruth& imu, Eigen::Vector3d& dp,
                        Eigen::Vector3d& dv, Eigen::Vector4d& dq) {
    dp = x.v;
    dv = x.q.toRotationMatrix() * imu.specific_force + earth.gravity(x.p) - 2.0 * omega.cross(x.v);
    const Eigen::Quaterniond wb(0, imu.angular_rate.x(), imu.angular_rate.y(),
                                imu.angular_rate.z());
    const Eigen::Quaterniond we(0, omega.x(), omega.y(), omega.z());
    dq = 0.5 * ((x.q * wb).coeffs() - (we * x.q).coeffs());
  };
  auto advance = [](const State& x, const Eigen::Vector3d& dp, const Eigen::Vector3d& dv,
                    const Eigen::Vector4d& dq, double h) {
    State y{x.p + h * dp, x.v + h * dv, x.q};
    y.q.coeffs() = x.q.coeffs() + h * dq;
    return y;
  };
  const Sample s0 = sample(0);
  State x{s0.p, s0.v, Eigen::Quaterniond(s0.r)};
  Sample a = s0;
  double worst = 0, worst_att = 0;
  for (std::int64_t k = 0; k + 2 <= n; k += 2) {
    const Sample mid = sample(k + 1), end = sample(k + 2);
    const double h = 2 * dt;
    Eigen::Vector3d p1, v1, p2, v2, p3, v3, p4, v4;
    Eigen::Vector4d q1, q2, q3, q4;
    derivative(x, a.imu, p1, v1, q1);
    derivative(advance(x, p1, v1, q1, h / 2), mid.imu, p2, v2, q2);
    derivative(advance(x, p2, v2, q2, h / 2), mid.imu, p3, v3, q3);
    derivative(advance(x, p3, v3, q3, h), end.imu, p4, v4, q4);
    x.p += h / 6 * (p1 + 2 * p2 + 2 * p3 + p4);
    x.v += h / 6 * (v1 + 2 * v2 + 2 * v3 + v4);
    x.q.coeffs() += h / 6 * (q1 + 2 * q2 + 2 * q3 + q4);
    x.q.normalize();
    worst = std::max(worst, (x.p - end.p).norm());
    worst_att =
        std::max(worst_att, Eigen::AngleAxisd(x.q.toRotationMatrix().transpose() * end.r).angle());
    a = end;
  }
  RecordProperty("position_error_m", std::to_string(worst));
  RecordProperty("attitude_error_rad", std::to_string(worst_att));
  EXPECT_GT((sample(n).p - s0.p).norm(), 5000.0);
  EXPECT_LT(worst, 0.01) << "attitude " << worst_att;
  EXPECT_LT(worst_att, 1e-5);
}

// The expanded gravity along a 20 km path agrees with the exact field to 1e-8 m/s².
TEST(Inertial, LocalGravityMatchesTheExactField) {
  const Earth earth({43.7228, 10.3966, 50.0});
  LocalGravity local(earth);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(1.0 * i, 0.3 * i, 50.0 * std::sin(i * 1e-3));
    worst = std::max(worst, (local.at(p) - earth.gravity(p)).norm());
  }
  EXPECT_LT(worst, 1e-8);
}

TEST(ErrorModel, QuantizationIsExactAndUnbiased) {
  TriadSpec s;
  s.resolution = 0.01;
  TriadErrorModel m(s, RandomStream(1, "q"), 0.01);
  double sum_err = 0;
  const Eigen::Vector3d x(0.123456, -0.0049, 7.77777);
  for (std::uint64_t k = 0; k < 10000; ++k) {
    const Eigen::Vector3d y = m.measure(k, x);
    for (int a = 0; a < 3; ++a) {
      const double steps = y[a] / 0.01;
      ASSERT_NEAR(steps, std::round(steps), 1e-9);  // multiples of the LSB only
    }
    sum_err += y.x() - x.x();
  }
  // Residual carry-over: the mean error vanishes (|Σ err| < one LSB over 10 000 readings).
  EXPECT_LT(std::abs(sum_err), 0.01);
}

TEST(ErrorModel, SaturationClipsExactly) {
  TriadSpec s;
  s.range = 2.0;
  s.noise_density = 0.01;
  TriadErrorModel m(s, RandomStream(1, "sat"), 0.01);
  for (std::uint64_t k = 0; k < 1000; ++k) {
    const Eigen::Vector3d y = m.measure(k, {5.0, -5.0, 1.0});
    ASSERT_EQ(y.x(), 2.0);
    ASSERT_EQ(y.y(), -2.0);
    ASSERT_LT(std::abs(y.z()), 2.0);
  }
}

// Allan deviation of long static runs recovers N (at τ = 1 s), K (on the +½ line at τ = 3 s)
// and B (floor / 0.664, at the middle of the floor) within 10 %, each term on its own run so
// that the others do not leak into its read-out point.
TEST(ErrorModel, AllanDeviationRecoversNoiseDensityRandomWalkAndBiasInstability) {
  const double dt = 0.01;           // 100 Hz
  const std::size_t n = 2'000'000;  // 5.6 h
  std::vector<double> x(n);
  auto record = [&](const TriadSpec& spec, std::uint64_t seed) {
    TriadErrorModel model(spec, RandomStream(seed, "allan"), dt);
    for (std::size_t k = 0; k < n; ++k)
      x[k] = model.measure(k, Eigen::Vector3d::Zero()).x();
  };
  TriadSpec white;
  white.noise_density = 1e-3;
  record(white, 7);
  EXPECT_NEAR(allanDeviation(x, dt, 100), white.noise_density, 0.10 * white.noise_density);

  TriadSpec flicker;
  flicker.bias_instability = 2e-4;
  flicker.bias_instability_tau_s = 100;
  record(flicker, 8);
  // The estimate's own uncertainty at 100 s is about 5 % with 5.6 h of data.
  const double floor = allanDeviation(x, dt, 10000);
  EXPECT_NEAR(floor / 0.664, flicker.bias_instability, 0.10 * flicker.bias_instability);
  // Flat over a decade around τ0 (a single Gauss–Markov process would not be).
  for (std::size_t m : {3000u, 30000u})
    EXPECT_NEAR(allanDeviation(x, dt, m), floor, 0.2 * floor) << "tau " << m * dt;

  TriadSpec rw;
  rw.random_walk = 1e-4;
  record(rw, 9);
  EXPECT_NEAR(allanDeviation(x, dt, 300), rw.random_walk, 0.10 * rw.random_walk);
}

// The bias-instability floor's shape, in closed form: 0.664·B at τ0 and flat within 2.5 %
// over two decades each side; beyond the outer correlation times it falls off.
TEST(ErrorModel, BiasInstabilityFloorIsFlatFromTwoDecadesBelowToThreeAbove) {
  TriadSpec spec;
  spec.bias_instability = 3e-5;
  spec.bias_instability_tau_s = 40.0;
  const TriadErrorModel model(spec, RandomStream(1, "floor"), 0.01);
  const double floor = 0.664 * spec.bias_instability;
  EXPECT_NEAR(std::sqrt(model.flickerAllanVariance(40.0)), floor, 1e-12 * floor);
  for (double decades = -2.0; decades <= 3.0 + 1e-9; decades += 0.05) {
    const double adev = std::sqrt(model.flickerAllanVariance(40.0 * std::pow(10.0, decades)));
    EXPECT_NEAR(adev, floor, 0.025 * floor) << decades << " decades from τ0";
  }
  EXPECT_LT(std::sqrt(model.flickerAllanVariance(40.0 * 1e6)), 0.5 * floor);
  EXPECT_LT(std::sqrt(model.flickerAllanVariance(40.0 * 1e-5)), 0.5 * floor);
}

// The overlapping Allan variance of a long record without holding it: the first `head`
// readings at full rate for short clusters, and the running integral at every `decimation`-th
// reading for long ones (clusters a multiple of it).
class AllanRecord {
 public:
  AllanRecord(double dt, std::size_t head, std::size_t decimation)
      : dt_(dt), head_(head), decimation_(decimation) {}
  void add(std::size_t k, double y) {
    if (k < head_)
      head_rate_.push_back(y);
    if (k % decimation_ == 0)
      theta_.push_back(running_);
    running_ += y * dt_;
  }
  /// Allan variance at about τ (clusters of the nearest usable size), and the τ used.
  std::pair<double, double> at(double tau) const {
    const auto m = static_cast<std::size_t>(std::max(1.0, std::round(tau / dt_)));
    if (4 * m * 10 <= head_rate_.size())
      return {std::pow(allanDeviation(head_rate_, dt_, m), 2), static_cast<double>(m) * dt_};
    const std::size_t j = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::round(tau / (dt_ * static_cast<double>(decimation_)))));
    const double t = static_cast<double>(j * decimation_) * dt_;
    long double sum = 0.0L;
    std::size_t count = 0;
    for (std::size_t k = 0; k + 2 * j < theta_.size(); ++k, ++count) {
      const double d = theta_[k + 2 * j] - 2.0 * theta_[k + j] + theta_[k];
      sum += static_cast<long double>(d) * d;
    }
    return {static_cast<double>(sum / (2.0L * t * t * static_cast<long double>(count))), t};
  }

 private:
  double dt_;
  std::size_t head_, decimation_;
  std::vector<double> head_rate_, theta_;
  double running_ = 0.0;
};

struct FittedTerms {
  double n, b, k;
};

// Weighted linear least squares of σ²(τ) = N²/τ + F² + K²τ/3 over τ four per decade from dt
// to a tenth of the record. Each point is weighted by its relative uncertainty √(τ/T) times
// the fitted model's value there, iterated from the measured values (weighting by the measured
// values alone would favour the points that came out low, and bias the slow terms low).
FittedTerms fitAllan(const std::vector<AllanRecord>& records, double dt, double duration) {
  std::vector<std::pair<double, double>> points;  // (τ, Allan variance averaged over records)
  for (double e = std::log10(dt); std::pow(10.0, e) <= 0.1 * duration; e += 0.25) {
    double avar = 0.0, tau = 0.0;
    for (const AllanRecord& r : records) {
      const auto [v, t] = r.at(std::pow(10.0, e));
      avar += v / static_cast<double>(records.size());
      tau = t;
    }
    if (points.empty() || tau != points.back().first)
      points.emplace_back(tau, avar);
  }
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < 8; ++iteration) {
    Eigen::Matrix3d lhs = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const auto& [tau, avar] : points) {
      const Eigen::Vector3d basis(1.0 / tau, 1.0, tau);
      const double expected = iteration == 0 ? avar : basis.dot(c);
      const double w = 1.0 / (expected * std::sqrt(tau / duration));
      lhs += w * w * basis * basis.transpose();
      rhs += w * w * basis * avar;
    }
    c = lhs.ldlt().solve(rhs);
  }
  return {std::sqrt(c[0]), std::sqrt(c[1]) / 0.664, std::sqrt(3.0 * c[2])};
}

// The simulated bias instability against its closed form at every scale: the fast terms
// (drawn at each reading as their interval means) and the held ones (updated at least ten
// times per correlation time) together give the Allan deviation of the continuous process, from
// one sample interval to a thousand seconds, within the estimate's own scatter.
TEST(ErrorModel, SimulatedFlickerMatchesItsClosedForm) {
  const double dt = 0.01, tau0 = 10.0, duration = 6.0 * 3600.0;
  TriadSpec spec;
  spec.bias_instability = 1e-4;
  spec.bias_instability_tau_s = tau0;
  TriadErrorModel model(spec, RandomStream(77, "closed form"), dt);
  const auto n = static_cast<std::size_t>(duration / dt);
  std::vector<AllanRecord> axes(3, AllanRecord(dt, static_cast<std::size_t>(3000.0 / dt), 10));
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d y = model.measure(k, Eigen::Vector3d::Zero());
    for (int a = 0; a < 3; ++a)
      axes[static_cast<std::size_t>(a)].add(k, y[a]);
  }
  for (double tau : {0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0}) {
    double avar = 0.0, used = 0.0;
    for (const AllanRecord& r : axes) {
      const auto [v, t] = r.at(tau);
      avar += v / 3.0;
      used = t;
    }
    const double expected = std::sqrt(model.flickerAllanVariance(used));
    // About 1/√(2·edf) with edf ≈ 3·T/τ clusters: 1 % at short τ, 8 % at 1000 s (3σ).
    const double tolerance = std::max(0.015, 3.0 / std::sqrt(2.0 * 3.0 * duration / used));
    EXPECT_NEAR(std::sqrt(avar), expected, tolerance * expected) << "tau " << used;
    std::printf("tau %g: %+.2f %% (tolerance %.1f %%)\n", used,
                100.0 * (std::sqrt(avar) / expected - 1.0), 100.0 * tolerance);
  }
}

// A 6 h static record with a datasheet whose white-noise and random-walk lines cross the bias
// floor two decades from the cluster time (N = F·√(τ0/100), K = F·√(3/(100·τ0)), F = 0.664·B):
// a weighted least-squares fit of the IEEE-952 model to the overlapping Allan variance, as a
// user would do with the output (on the triad's mean Allan variance), recovers N, B and K
// within 10 %.
TEST(ErrorModel, SixHourStaticRunRecoversTheDatasheet) {
  // The random-walk line crosses at 100·τ0 = 20 s, early enough in 6 h for K to be known to
  // a few per cent (its estimate's spread over seeds is about 3 %, the others' 0.2 %); the
  // white-noise line crosses at 2 ms, seen at 1 kHz.
  const double rate = 1000.0, dt = 1.0 / rate;
  const double tau0 = 0.2, b = 2e-5, f = 0.664 * b;
  const std::uint64_t seed = 2026;
  TriadSpec spec;
  spec.bias_instability = b;
  spec.bias_instability_tau_s = tau0;
  spec.noise_density = f * std::sqrt(tau0 / 100.0);
  spec.random_walk = f * std::sqrt(3.0 / (100.0 * tau0));
  const double duration = 6.0 * 3600.0;
  const auto n = static_cast<std::size_t>(duration * rate);
  std::vector<AllanRecord> axes(3, AllanRecord(dt, static_cast<std::size_t>(2000.0 * rate),
                                               static_cast<std::size_t>(0.1 * rate)));
  TriadErrorModel model(spec, RandomStream(seed, "datasheet"), dt);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d y = model.measure(k, Eigen::Vector3d::Zero());
    for (int a = 0; a < 3; ++a)
      axes[static_cast<std::size_t>(a)].add(k, y[a]);
  }
  const auto report = [&](const FittedTerms& fit, const char* what) {
    std::printf("%s: N %+.1f %%, B %+.1f %%, K %+.1f %%\n", what,
                100.0 * (fit.n / spec.noise_density - 1.0), 100.0 * (fit.b / b - 1.0),
                100.0 * (fit.k / spec.random_walk - 1.0));
  };
  for (std::size_t a = 0; a < 3; ++a)
    report(fitAllan({axes[a]}, dt, duration), a == 0 ? "x" : a == 1 ? "y" : "z");
  const FittedTerms fit = fitAllan(axes, dt, duration);
  report(fit, "triad");
  EXPECT_NEAR(fit.n, spec.noise_density, 0.10 * spec.noise_density);
  EXPECT_NEAR(fit.b, b, 0.10 * b);
  EXPECT_NEAR(fit.k, spec.random_walk, 0.10 * spec.random_walk);
}

// The integrated angle random walk after T seconds has std N √T whatever the sample rate.
TEST(ErrorModel, IntegratedNoiseIsInvariantToTheSampleRate) {
  TriadSpec s;
  s.noise_density = 2e-3;
  const double duration = 10.0;
  for (double rate : {100.0, 400.0, 1000.0}) {
    const double dt = 1.0 / rate;
    const auto steps = static_cast<std::uint64_t>(duration * rate);
    double sum2 = 0;
    const int runs = 400;
    for (int r = 0; r < runs; ++r) {
      TriadErrorModel m(s, RandomStream(100 + r, "rate"), dt);
      double angle = 0;
      for (std::uint64_t k = 0; k < steps; ++k)
        angle += m.measure(k, Eigen::Vector3d::Zero()).x() * dt;
      sum2 += angle * angle;
    }
    const double sd = std::sqrt(sum2 / runs);
    // 400 runs: the std estimate is within ±3.5/√(2·400) ≈ 12 % at 3.5σ.
    EXPECT_NEAR(sd, s.noise_density * std::sqrt(duration),
                0.12 * s.noise_density * std::sqrt(duration))
        << rate << " Hz";
  }
}

TEST(ErrorModel, SameSeedSameOutputAndStateResumes) {
  TriadSpec s;
  s.noise_density = 1e-3;
  s.bias_instability = 1e-4;
  s.random_walk = 1e-5;
  s.resolution = 1e-4;
  TriadErrorModel a(s, RandomStream(3, "x"), 0.01), b(s, RandomStream(3, "x"), 0.01);
  for (std::uint64_t k = 0; k < 500; ++k)
    a.measure(k, Eigen::Vector3d(1, 2, 3));
  const nlohmann::json state = a.state();
  for (std::uint64_t k = 0; k < 500; ++k)
    b.measure(k, Eigen::Vector3d(1, 2, 3));
  TriadErrorModel c(s, RandomStream(3, "x"), 0.01);
  c.restore(nlohmann::json::parse(state.dump()));  // through text, as in a checkpoint
  for (std::uint64_t k = 500; k < 600; ++k) {
    const Eigen::Vector3d yb = b.measure(k, Eigen::Vector3d(1, 2, 3));
    const Eigen::Vector3d yc = c.measure(k, Eigen::Vector3d(1, 2, 3));
    ASSERT_EQ(yb, yc);
  }
}

}  // namespace
}  // namespace trainsim::inertial
