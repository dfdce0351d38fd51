#include "trainsim/positioning/odometer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trainsim::positioning {

double OdometerSpec::pulseLength_m() const {
  return std::numbers::pi * wheel_diameter_m / static_cast<double>(pulses_per_revolution);
}

OdometerModel::OdometerModel(const OdometerSpec& spec, TimeNs period, RandomStream random)
    : spec_(spec), period_(period), random_(random), pulse_m_(spec.pulseLength_m()) {}

OdometerReading OdometerModel::step(std::uint64_t k, TimeNs t, double distance_m,
                                    double accel_m_s2) {
  if (!started_) {
    last_distance_m_ = distance_m;
    started_ = true;
  }
  const OdometerSpec::Slip& slip = spec_.slip;
  if (slip.enabled && t >= episode_end_) {
    episode_factor_ = 0.0;
    const auto u = random_.uniform4(k);
    const bool traction = accel_m_s2 > slip.accel_threshold_m_s2;
    const bool braking = accel_m_s2 < -slip.brake_threshold_m_s2;
    if ((traction || braking) && u[0] < slip.rate_per_s * toSeconds(period_)) {
      const double magnitude = 0.02 + (slip.magnitude_max - 0.02) * u[1];
      episode_factor_ = traction ? magnitude : -std::min(magnitude, 0.9);
      episode_end_ =
          t + fromSeconds(slip.duration_min_s + (slip.duration_max_s - slip.duration_min_s) * u[2]);
    }
  }
  const double ds = distance_m - last_distance_m_;
  last_distance_m_ = distance_m;
  encoder_m_ += (1.0 + spec_.scale_error) * (1.0 + episode_factor_) * ds;
  OdometerReading r;
  r.pulses = static_cast<std::int64_t>(std::floor(encoder_m_ / pulse_m_));
  r.distance_m = static_cast<double>(r.pulses) * pulse_m_;
  r.speed_m_s =
      k == 0 ? 0.0 : static_cast<double>(r.pulses - last_pulses_) * pulse_m_ / toSeconds(period_);
  last_pulses_ = r.pulses;
  r.slip = episode_factor_ > 0 ? 1 : episode_factor_ < 0 ? -1 : 0;
  return r;
}

nlohmann::json OdometerModel::state() const {
  return {{"encoder_m", encoder_m_},
          {"last_u", last_distance_m_},
          {"last_pulses", last_pulses_},
          {"episode_end_ns", episode_end_},
          {"episode_factor", episode_factor_}};
}

void OdometerModel::restore(const nlohmann::json& state) {
  encoder_m_ = state.at("encoder_m").get<double>();
  last_distance_m_ = state.at("last_u").get<double>();
  last_pulses_ = state.at("last_pulses").get<std::int64_t>();
  episode_end_ = state.at("episode_end_ns").get<TimeNs>();
  episode_factor_ = state.at("episode_factor").get<double>();
  started_ = true;
}

}  // namespace trainsim::positioning
