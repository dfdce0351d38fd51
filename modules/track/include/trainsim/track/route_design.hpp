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
  double length_m = 6000.0;
  double radius_min_m = 0.0;  ///< 0: the minimum radius for the design speed
  double radius_max_m = 4000.0;
  double curve_share = 0.4;  ///< fraction of the length in curves (transitions included)
  double arc_length_min_m = 150.0;
  double arc_length_max_m = 800.0;
  SpecialBlockParams station{0.3, 250.0, 250.0};
  SpecialBlockParams tunnel{0.15, 200.0, 800.0};
  SpecialBlockParams bridge{0.15, 50.0, 300.0};
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

/// One block of a route given as an explicit list (route.source = "blocks"): what a designer
/// edits in the studio's block table.
enum class Turn { kLeft, kRight };
inline constexpr EnumName<Turn> kTurnNames[] = {{Turn::kLeft, "left"}, {Turn::kRight, "right"}};
constexpr std::span<const EnumName<Turn>> enumNames(Turn) {
  return kTurnNames;
}

struct BlockSpec {
  BlockType type = BlockType::kStraight;  ///< straight, curve, station, tunnel or bridge
  /// Straight-like blocks: their length; curves: the length of the circular arc alone.
  double length_m = 500.0;
  double radius_m = 1500.0;      ///< curves: arc radius (> 0)
  Turn direction = Turn::kLeft;  ///< curves: the way the curve turns
  double transition_m = -1.0;    ///< curves: each transition; < 0 chooses the design minimum
  double cant_m = -1.0;          ///< curves: applied cant magnitude; < 0 lets the rules choose
  double grade = 0.0;            ///< tan θ of the grade from the start of this block on
};

/// Lays out a route block by block, starting east at the origin. Grade changes at block starts
/// are joined by vertical curves of 1.2 × the minimum vertical radius (rounded up to 500 m),
/// reduced where neighbours leave no room (reported as vertical_fit). Curves take the design
/// minimum transition (≥ 20 m, in 5 m steps) and the rules' applied cant unless given; rule
/// breaks are left to checkDesign. Throws ConfigError naming "route.blocks[i]" for blocks that
/// cannot be laid out at all (no length, no radius, a switch).
DesignedRoute buildBlockRoute(const std::vector<BlockSpec>& blocks, const RouteOptions& options);

/// The block list that lays out `route` again: types, lengths, radii, transitions and cant are
/// exact; each block's grade is its mean grade (the vertical curves become the automatic ones).
std::vector<BlockSpec> blockSpecs(const Route& route);

}  // namespace trainsim::track
