#pragma once

#include <utility>
#include <vector>

#include "trainsim/track/route.hpp"

namespace trainsim::track {

/// Longitudinal limits of the train (docs/REFERENCES.md R1.6).
struct MotionLimits {
  double accel_m_s2 = 0.8;
  double brake_m_s2 = 0.6;  ///< service braking
  double jerk_m_s3 = 0.6;
  double train_length_m = 100.0;  ///< a restriction holds until the whole train has left it
};

/// Optional running resistance and traction: the acceleration available at speed v on grade θ
/// is min(accel, (F(v) − R(v)) / (m ρ) − g sin θ), with F(v) = min(F_max, P/v) and Davis
/// R(v) = A + B v + C v².
struct TrainDynamics {
  bool enabled = false;
  double mass_kg = 260e3;
  double rotating_mass_factor = 1.05;
  double davis_a_n = 2288.0;
  double davis_b_n_s_m = 68.33;
  double davis_c_n_s2_m2 = 7.75;
  double max_traction_n = 242e3;
  double max_power_w = 1.8e6;

  double availableAccel(double v, double sin_grade) const;
};

/// One piece of the motion with constant jerk, starting at t0 with (u0, v0, a0).
struct MotionSegment {
  double t0_s = 0.0;
  double u0_m = 0.0;
  double v0_m_s = 0.0;
  double a0_m_s2 = 0.0;
  double jerk_m_s3 = 0.0;
  double duration_s = 0.0;
};

/// Position u (front bogie, distance along the track in 3D), speed, acceleration and jerk.
struct MotionState {
  double u_m = 0.0;
  double v_m_s = 0.0;
  double a_m_s2 = 0.0;
  double jerk_m_s3 = 0.0;
};

/// A piecewise-constant speed limit over the front bogie's distance u.
struct SpeedLimit {
  std::vector<double> u_begin_m;  ///< sorted; the last piece runs to infinity
  std::vector<double> limit_m_s;
  double at(double u) const;
};

/// The motion as a chain of constant-jerk segments: exact cubic in time, so sampling it at any
/// period gives exact position, speed, acceleration and jerk.
class MotionProfile {
 public:
  MotionProfile() = default;
  MotionProfile(std::vector<MotionSegment> segments, SpeedLimit limit);
  const std::vector<MotionSegment>& segments() const { return segments_; }
  const SpeedLimit& limit() const { return limit_; }
  double duration() const;
  MotionState at(double t_s) const;
  /// The first time the train reaches distance u (by bisection on the monotone cubic of the
  /// segment that reaches it, to 1e-12 s); the start or end time outside the run.
  double timeAtDistance(double u_m) const;

  /// The same run with the train at rest for `before_s` at its start position before it
  /// departs and for `after_s` where it ends after it arrives (IMU alignment, calibration).
  MotionProfile withStandstill(double before_s, double after_s) const;
  /// A train that stands at `u_m` for `duration_s` and never moves (static calibration data).
  static MotionProfile standstill(double u_m, double duration_s, SpeedLimit limit);

 private:
  std::vector<MotionSegment> segments_;
  SpeedLimit limit_;
};

/// Time-optimal jerk-limited (S-curve) run from rest at `u_start` to rest at `u_end` under the
/// speed limit in force (block and curve limits, each held until the train has cleared it),
/// stopping at each (chainage, dwell) stop on the way. Acceleration is zero at every change of
/// limit; acceleration phases use the lower of `limits.accel_m_s2` and what the dynamics allow
/// on the section's steepest climb at the section's speeds.
MotionProfile planMotion(const Route& route, const std::vector<std::pair<double, double>>& stops,
                         const MotionLimits& limits, const TrainDynamics& dynamics, double u_start,
                         double u_end);

}  // namespace trainsim::track
