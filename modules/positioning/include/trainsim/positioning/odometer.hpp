#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "trainsim/core/random.hpp"
#include "trainsim/core/time.hpp"

namespace trainsim::positioning {

/// A wheel encoder and how its wheel slips (docs/REFERENCES.md R4).
struct OdometerSpec {
  double wheel_diameter_m = 0.92;
  int pulses_per_revolution = 200;
  /// The encoder reads (1 + scale_error) times the distance travelled (worn or mis-calibrated
  /// wheel).
  double scale_error = 0.005;
  struct Slip {
    bool enabled = true;
    double accel_threshold_m_s2 = 0.5;  ///< slip (traction) only above this acceleration
    double brake_threshold_m_s2 = 0.4;  ///< slide (braking) only above this deceleration
    double rate_per_s = 0.02;           ///< episode start rate while above a threshold
    double duration_min_s = 1.0;
    double duration_max_s = 4.0;
    double magnitude_max = 0.15;  ///< largest relative speed error of an episode
  } slip;

  double pulseLength_m() const;
};

/// One odometer reading.
struct OdometerReading {
  std::int64_t pulses = 0;  ///< cumulative whole pulses
  double distance_m = 0.0;  ///< pulses · π D / N
  double speed_m_s = 0.0;   ///< pulse difference over the period (0 at the first reading)
  int slip = 0;             ///< 1 slip, −1 slide, 0 none
};

/// The encoder sees the wheel turn (1 + ε)(1 + e)·ds, where e is the relative speed error of
/// a slip (e > 0, under traction) or slide (e < 0, under braking) episode. Episodes start
/// only while the acceleration is beyond its threshold, with probability rate · T per reading,
/// and last a drawn duration. Pulses are whole pulses of the encoder distance.
///
/// Draws are keyed by (seed, stream, reading index k); the encoder and the episode are carried
/// in state()/restore(). Not thread-safe: step() advances the state, in time order.
class OdometerModel {
 public:
  OdometerModel(const OdometerSpec& spec, TimeNs period, RandomStream random);

  /// The reading at sample k, time t, when the wheel has run `distance_m` in total (any
  /// origin: only differences count) and the train accelerates at `accel_m_s2`.
  OdometerReading step(std::uint64_t k, TimeNs t, double distance_m, double accel_m_s2);

  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

 private:
  OdometerSpec spec_;
  TimeNs period_;
  RandomStream random_;
  double pulse_m_;
  double encoder_m_ = 0.0, last_distance_m_ = 0.0;
  std::int64_t last_pulses_ = 0;
  TimeNs episode_end_ = 0;
  double episode_factor_ = 0.0;
  bool started_ = false;
};

}  // namespace trainsim::positioning
