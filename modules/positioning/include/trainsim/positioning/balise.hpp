#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainsim/core/random.hpp"
#include "trainsim/core/time.hpp"

namespace trainsim::positioning {

/// Where balise groups lie along a track (docs/REFERENCES.md R5).
struct BalisePlacement {
  double first_group_m = 200.0;      ///< distance of the first group from the track start
  double group_spacing_m = 1000.0;   ///< between groups
  int balises_per_group = 2;         ///< balises in a group
  double balise_spacing_m = 3.0;     ///< between the balises of a group
  double station_approach_m = 50.0;  ///< an extra group this far before each station; 0: none
};

struct Balise {
  int group = 0;
  int index = 0;     ///< within its group
  double u_m = 0.0;  ///< distance along the track (3D)
};

/// Balise groups every group_spacing_m from first_group_m while a whole group fits before
/// `track_length_m`, plus one group station_approach_m before each station start (distances
/// along the track, 3D). Sorted by distance; groups numbered in that order.
std::vector<Balise> placeBalises(const BalisePlacement& placement, double track_length_m,
                                 std::span<const double> station_starts_m);

/// The reader antenna at one instant: time, distance along the track, speed.
struct AntennaState {
  TimeNs t = 0;
  double u_m = 0.0;
  double v_m_s = 0.0;
};

/// The time at which the antenna reaches distance `target_m` between states a and b, on the
/// cubic Hermite interpolant of u(t) through both (exact speeds at both ends), rounded to the
/// nanosecond. `target_m` must lie in [a.u_m, b.u_m]; the interpolant is monotone when the
/// train does not reverse.
TimeNs passageTime(const AntennaState& a, const AntennaState& b, double target_m);

/// One balise read: its own passage time, not the polling sample's.
struct BaliseEvent {
  TimeNs t = 0;
  const Balise* balise = nullptr;
};

/// The reader: at each polling instant, the balises the antenna passed since the previous one,
/// each detected where the antenna is at the balise plus a Gaussian detection error (keyed by
/// the balise's index, so independent of the polling rate). Balises behind the antenna at its
/// first state are never read. Carries its last state in state()/restore(); not thread-safe.
class BaliseDetector {
 public:
  BaliseDetector(std::vector<Balise> balises, double detection_sigma_m, RandomStream random);

  /// The events between the previous state and `now`, in order.
  std::vector<BaliseEvent> step(const AntennaState& now);

  const std::vector<Balise>& balises() const { return balises_; }
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

 private:
  std::vector<Balise> balises_;
  double detection_sigma_m_;
  RandomStream random_;
  std::size_t next_ = 0;
  AntennaState previous_;
  bool started_ = false;
};

}  // namespace trainsim::positioning
