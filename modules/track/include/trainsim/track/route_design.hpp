#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::track {

/// Settings shared by generated and imported routes.
struct RouteOptions {
  DesignRules rules;
  TransitionShape transition_shape = TransitionShape::kClothoid;
  CantRotation cant_rotation = CantRotation::kCentre;
  double station_dwell_s = 30.0;
  bool station_stops = true;
};

/// Special stretches placed on straights by the random generator.
struct SpecialBlockParams {
  double probability = 0.0;  ///< per straight stretch
  double length_min_m = 0.0;
  double length_max_m = 0.0;
};

/// Parameters of the seeded random route generator.
struct RouteGeneratorParams {
  double length_m = 5000.0;
  double radius_min_m = 0.0;  ///< 0: the minimum radius for the design speed
  double radius_max_m = 4000.0;
  double curve_share = 0.4;  ///< fraction of the length in curves (transitions included)
  double arc_length_min_m = 150.0;
  double arc_length_max_m = 800.0;
  SpecialBlockParams station{0.25, 250.0, 250.0};
  SpecialBlockParams tunnel{0.1, 200.0, 1000.0};
  SpecialBlockParams bridge{0.1, 50.0, 400.0};
  double grade_max = 0.0125;  ///< largest |tan θ| drawn (≤ rules.max_grade)
  double grade_length_min_m = 600.0;
  double grade_length_max_m = 2500.0;
};

/// A route and what went into it.
struct DesignedRoute {
  Route route;
  /// Stations where the train stops: (chainage of the stop point, dwell time in s).
  std::vector<std::pair<double, double>> stops;
  /// Problems found while fitting (radii reduced to fit, ...), reported with the design rules.
  std::vector<Violation> fitting;
};

/// A random route obeying `options.rules`, a pure function of (params, options, seed).
DesignedRoute generateRoute(const RouteGeneratorParams& params, const RouteOptions& options,
                            std::uint64_t seed);

/// Waypoint-import settings.
struct WaypointParams {
  double radius_max_m = 50000.0;  ///< largest radius chosen where the file gives none
};

/// Imports a route from a CSV of waypoints (points of intersection of the straights). Header
/// columns: either `n_m,e_m,d_m` (local NED at the scenario's origin) or
/// `latitude_deg,longitude_deg,height_m` (ellipsoidal height; `altitude_m` is accepted too),
/// and optionally `radius_m` (arc radius at this point; empty or 0 chooses the largest that
/// fits), `vertical_radius_m`, and `block` (station, tunnel, bridge or straight: the type of
/// the straight that leaves this point). Malformed files throw ConfigError naming file:line.
DesignedRoute importWaypoints(const std::filesystem::path& csv, const GeodeticAnchor& anchor,
                              const WaypointParams& params, const RouteOptions& options);

}  // namespace trainsim::track
