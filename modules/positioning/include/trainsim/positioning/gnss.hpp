#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "trainsim/core/random.hpp"
#include "trainsim/core/time.hpp"

namespace trainsim::positioning {

/// Error budget of a GNSS receiver, 1 sigma per axis, local east/north/up at the antenna.
struct GnssErrorSpec {
  double horizontal_sigma_m = 1.5;      ///< Gauss–Markov position error, east and north
  double vertical_sigma_m = 3.0;        ///< Gauss–Markov position error, up
  double correlation_time_s = 120.0;    ///< of every Gauss–Markov term
  double white_sigma_m = 0.3;           ///< white position noise
  double velocity_sigma_m_s = 0.05;     ///< white velocity noise
  double velocity_gm_sigma_m_s = 0.02;  ///< Gauss–Markov velocity error
};

/// Position and velocity errors of one fix, local east/north/up.
struct GnssErrors {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
};

/// GNSS errors: first-order Gauss–Markov processes (exactly discretised, x' = φ x + σ √(1−φ²) n,
/// φ = exp(−T/τ)) plus white noise, for position and velocity (docs/REFERENCES.md R3). The
/// first reading starts from the stationary distribution.
///
/// Random numbers are keyed by (seed, stream, reading index k), so a run's errors do not
/// depend on threads or on where it was resumed; the Gauss–Markov states are carried in
/// state()/restore(). Not thread-safe: step() advances the state, one reading after another.
class GnssErrorModel {
 public:
  GnssErrorModel(const GnssErrorSpec& spec, TimeNs period, RandomStream random);

  /// Advances the Gauss–Markov states to reading k and returns its errors. The processes run
  /// through outages too (the satellites' geometry does not stop), so call it at every reading.
  GnssErrors step(std::uint64_t k);

  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

 private:
  GnssErrorSpec spec_;
  RandomStream random_;
  double phi_;
  std::array<double, 3> position_gm_{};
  std::array<double, 3> velocity_gm_{};
  bool started_ = false;
};

/// Fix availability along a route: no fix while the antenna is inside a tunnel, and none until
/// `reacquisition` has passed since the antenna left it. The rule is timed from the exit itself,
/// not from the last reading inside: the fix at time t is lost iff the antenna, at time
/// t − reacquisition, had not yet passed the end of the last tunnel behind it. That needs the
/// antenna's chainage at one earlier time (it never goes backwards), so the rule is a pure
/// function of the trajectory, exact to the nanosecond at any sample rate, and carries no state.
class GnssVisibility {
 public:
  /// `tunnels`: [begin, end] chainages of the tunnels along the route, in order.
  GnssVisibility(std::vector<std::pair<double, double>> tunnels, TimeNs reacquisition);

  /// Whether the antenna is inside a tunnel at chainage c (ends included).
  bool inTunnel(double chainage_m) const;
  /// Whether the reading at time t has a fix; `antenna_chainage(t)` gives where the antenna
  /// is at any time t (monotone non-decreasing).
  bool fix(TimeNs t, const std::function<double(TimeNs)>& antenna_chainage) const;

 private:
  // The first tunnel that ends at or after chainage c.
  std::vector<std::pair<double, double>>::const_iterator firstEndingFrom(double c) const;

  std::vector<std::pair<double, double>> tunnels_;
  TimeNs reacquisition_;
};

}  // namespace trainsim::positioning
