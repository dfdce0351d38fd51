#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/track/track.hpp"

namespace trainsim::track {

/// What a stretch of track is. `kSwitch` is reserved for turnouts on the main line.
enum class BlockType { kStraight, kCurve, kStation, kTunnel, kBridge, kSwitch };

/// Names in scenario files (route.blocks[].type), railroad.json and waypoint CSVs.
inline constexpr EnumName<BlockType> kBlockTypeNames[] = {
    {BlockType::kStraight, "straight"}, {BlockType::kCurve, "curve"},
    {BlockType::kStation, "station"},   {BlockType::kTunnel, "tunnel"},
    {BlockType::kBridge, "bridge"},     {BlockType::kSwitch, "switch"}};
constexpr std::span<const EnumName<BlockType>> enumNames(BlockType) {
  return kBlockTypeNames;
}

/// A contiguous stretch of the main track with one type and speed limit. Blocks tile the
/// route: each starts where the previous one ends.
struct Block {
  int id = 0;
  BlockType type = BlockType::kStraight;
  double chainage_begin_m = 0.0;
  double chainage_end_m = 0.0;
  double speed_limit_m_s = 0.0;
  /// Curves: radius of the circular arc (signed, positive left) and its applied cant (signed
  /// as in CantProfile); zero elsewhere.
  double radius_m = 0.0;
  double cant_m = 0.0;
  bool stop = false;  ///< stations: the train stops here
};

/// Railway design limits (docs/REFERENCES.md R1.2–R1.4). Speeds in m/s, cant in m.
struct DesignRules {
  double design_speed_m_s = 160.0 / 3.6;
  double max_cant_m = 0.160;
  double max_cant_deficiency_m = 0.130;
  double max_cant_rate_m_s = 0.050;        ///< dD/dt
  double max_deficiency_rate_m_s = 0.055;  ///< dI/dt
  double max_cant_gradient = 2.25e-3;      ///< dD/ds, m/m (1:444)
  double min_element_duration_s = 1.8;     ///< straights and arcs last at least this at speed
  double max_grade = 0.0125;               ///< tan θ
  double max_vertical_accel_m_s2 = 0.2;    ///< R_v ≥ v² / a_v
  double station_max_grade = 0.0025;
  double station_max_cant_m = 0.060;
  double station_speed_m_s = 60.0 / 3.6;
  double tunnel_speed_m_s = 120.0 / 3.6;
  double bridge_speed_m_s = 120.0 / 3.6;

  /// Equilibrium cant s v²/(g R) for speed v on radius R.
  double equilibriumCant(double speed_m_s, double radius_m) const;
  /// R_min = b v² / (g (D_max + I_max)).
  double minRadius(double speed_m_s) const;
  /// Applied cant chosen for a curve run at `speed`: at least E − I_max, otherwise 2/3 E
  /// rounded to 5 mm, never above D_max; no cant below 40 km/h.
  double appliedCant(double speed_m_s, double radius_m) const;
  /// Highest speed on radius R with applied cant D: sqrt((D + I_max) g R / b).
  double curveSpeed(double radius_m, double cant_m) const;
  /// Shortest transition for a change of cant ΔD and deficiency ΔI at speed v:
  /// max(v ΔD/(dD/dt), v ΔI/(dI/dt), ΔD/(dD/ds)).
  double minTransitionLength(double speed_m_s, double cant_change_m,
                             double deficiency_change_m) const;
  double minElementLength(double speed_m_s) const { return min_element_duration_s * speed_m_s; }
  double minVerticalRadius(double speed_m_s) const {
    return speed_m_s * speed_m_s / max_vertical_accel_m_s2;
  }
  /// Speed limit of a block of this type (design speed for straights and curves).
  double blockSpeed(BlockType type) const;
};

/// The main track and its blocks.
struct Route {
  Track track;
  std::vector<Block> blocks;

  /// The block containing chainage s (the later one at a boundary).
  const Block& blockAt(double s) const;
};

/// One broken design rule, where it is broken, by how much.
struct Violation {
  std::string rule;
  double chainage_begin_m = 0.0;
  double chainage_end_m = 0.0;
  int block_id = -1;
  double value = 0.0;
  double limit = 0.0;
  std::string unit;
  std::string message;
};

/// Checks the route's geometry against the rules, at the speed each stretch is designed for
/// (the design speed, or the station/tunnel/bridge limit where lower). Returns every violation
/// in chainage order.
std::vector<Violation> checkDesign(const Route& route, const DesignRules& rules);

/// Speed limit in force for the train at chainage s: the block's limit, and on curves the
/// curve speed from cant plus allowed deficiency.
double speedLimitAt(const Route& route, double s);

}  // namespace trainsim::track
