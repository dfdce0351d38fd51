#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "trainsim/track/route.hpp"

namespace trainsim::track {

/// The turnouts the layout generator lays: diverging radius and crossing ratio 1:n.
enum class TurnoutType { k190_1_9, k500_1_12 };
inline constexpr EnumName<TurnoutType> kTurnoutTypeNames[] = {{TurnoutType::k190_1_9, "190-1:9"},
                                                              {TurnoutType::k500_1_12, "500-1:12"}};
constexpr std::span<const EnumName<TurnoutType>> enumNames(TurnoutType) {
  return kTurnoutTypeNames;
}

/// A simple turnout: diverging-track radius at the track centreline and crossing angle
/// tan α = 1/ratio (docs/REFERENCES.md R1.5).
struct Turnout {
  double radius_m;
  double ratio;  ///< n of 1:n
};

/// The geometry of a turnout type: "190-1:9" is R 190 m, 1:9; "500-1:12" is R 500 m, 1:12.
Turnout turnoutGeometry(TurnoutType type);

/// Which side of the main track auxiliary tracks are laid on (seen in the direction of
/// increasing chainage).
enum class AuxSide { kLeft, kRight, kEither };
inline constexpr EnumName<AuxSide> kAuxSideNames[] = {
    {AuxSide::kLeft, "left"}, {AuxSide::kRight, "right"}, {AuxSide::kEither, "either"}};
constexpr std::span<const EnumName<AuxSide>> enumNames(AuxSide) {
  return kAuxSideNames;
}

/// Parameters of the multi-track generator. Lengths in m, along main chainage unless noted.
struct LayoutParams {
  bool double_track = true;              ///< a second track on the right of the main track
  double track_centre_distance_m = 4.0;  ///< d, between neighbouring track centrelines
  double polyline_spacing_m = 2.0;       ///< largest 3D distance between polyline points
  double aux_probability = 0.3;          ///< per eligible stretch of the main track
  double aux_parallel_min_m = 300.0;     ///< length of the parallel part
  double aux_parallel_max_m = 800.0;
  double turnout_probability =
      0.5;  ///< per end: turnout from the neighbouring track, else dead end
  TurnoutType turnout = TurnoutType::k190_1_9;
  double dead_end_length_m = 40.0;  ///< the dead-end straight of an entering/outgoing part (plan)
  AuxSide side = AuxSide::kEither;
};

/// What a stretch of a layout track is: on the main and double track the main block's type;
/// on auxiliary tracks `kDeadEnd` (the straight ending at the buffer stop), `kTurnout` (the
/// diverging arc of the turnout and the straight diagonal after it), `kCurve` (the arc that
/// turns the track parallel, or away from it) and `kParallel`.
enum class LayoutBlockType {
  kStraight,
  kCurve,
  kStation,
  kTunnel,
  kBridge,
  kSwitch,
  kDeadEnd,
  kTurnout,
  kParallel
};
inline constexpr EnumName<LayoutBlockType> kLayoutBlockTypeNames[] = {
    {LayoutBlockType::kStraight, "straight"}, {LayoutBlockType::kCurve, "curve"},
    {LayoutBlockType::kStation, "station"},   {LayoutBlockType::kTunnel, "tunnel"},
    {LayoutBlockType::kBridge, "bridge"},     {LayoutBlockType::kSwitch, "switch"},
    {LayoutBlockType::kDeadEnd, "dead_end"},  {LayoutBlockType::kTurnout, "turnout"},
    {LayoutBlockType::kParallel, "parallel"}};
constexpr std::span<const EnumName<LayoutBlockType>> enumNames(LayoutBlockType) {
  return kLayoutBlockTypeNames;
}
/// The layout block type of a main-track block type (same name).
LayoutBlockType layoutBlockType(BlockType type);

/// Which part of an auxiliary track a block belongs to; kWhole on the main and double track.
enum class TrackPart { kWhole, kEntering, kParallel, kOutgoing };
inline constexpr EnumName<TrackPart> kTrackPartNames[] = {{TrackPart::kWhole, "whole"},
                                                          {TrackPart::kEntering, "entering"},
                                                          {TrackPart::kParallel, "parallel"},
                                                          {TrackPart::kOutgoing, "outgoing"}};
constexpr std::span<const EnumName<TrackPart>> enumNames(TrackPart) {
  return kTrackPartNames;
}

/// A stretch of one layout track with one type.
struct LayoutBlock {
  LayoutBlockType type = LayoutBlockType::kStraight;
  TrackPart part = TrackPart::kWhole;
  double begin_m = 0.0;  ///< distance along this track's own polyline
  double end_m = 0.0;
  /// The main-track block alongside, where there is one (main and double track: the route
  /// block this block copies).
  int main_block_id = -1;
};

/// The lateral offset y(x) of a layout track from the main track at main chainage x (+ left,
/// in plan): a line between (x0, y0) and (x1, y1), or an arc of radius r tangent at xt to the
/// parallel at yt, bending towards `bend` (±1): y = yt + bend·(r − sqrt(r² − (x − xt)²)).
struct OffsetPiece {
  enum class Shape { kLine, kArc };
  Shape shape = Shape::kLine;
  double x0 = 0.0, x1 = 0.0;
  double y0 = 0.0, y1 = 0.0;
  double xt = 0.0, yt = 0.0, bend = 0.0, r = 0.0;

  double offset(double x) const;
  double slope(double x) const;  ///< dy/dx
  static OffsetPiece line(double x0, double x1, double y0, double y1);
};

/// The frame of a layout track at one place: the centreline point at top of rail, the unit
/// tangent (direction of travel along the track), the unit left normal across the track in the
/// plane of the rails (horizontal for zero roll) and up = tangent × left; roll is the cant
/// angle (positive with the left rail higher), which every track takes from the main track at
/// the same chainage (auxiliary tracks lie beside straights, where it is zero).
struct TrackFrame {
  double main_chainage_m = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
  Eigen::Vector3d left = Eigen::Vector3d::UnitY();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double roll_rad = 0.0;
};

/// What a layout track is.
enum class TrackKind { kMain, kDouble, kAuxiliary };
inline constexpr EnumName<TrackKind> kTrackKindNames[] = {{TrackKind::kMain, "main"},
                                                          {TrackKind::kDouble, "double"},
                                                          {TrackKind::kAuxiliary, "auxiliary"}};
constexpr std::span<const EnumName<TrackKind>> enumNames(TrackKind) {
  return kTrackKindNames;
}

/// A stretch of a layout track's polyline: main chainage [x0, x1] sampled uniformly, with the
/// points at x0 + (x1 − x0)·i/n for i = 1..n on the offset piece `piece`. The stretch begins at
/// the previous run's last point (the first run at its own point at x0). Runs span at most
/// `kPolylineRunLength_m` of main chainage, so a track is O(its length / 500 m) numbers, and
/// a stretch of its polyline is made on demand (samplePolyline) without holding the rest.
struct PolylineRun {
  double x0 = 0.0, x1 = 0.0;
  double distance_begin_m = 0.0, distance_end_m = 0.0;  ///< along-polyline (3D chord) distance
  std::uint32_t n = 1;
  std::int32_t piece = 0;  ///< index into LayoutTrack::offset
};
inline constexpr double kPolylineRunLength_m = 500.0;

/// One track of the layout: a lateral offset law from the main track and the runs that sample
/// it into a polyline in the world frame (ENU, m), at most `polyline_spacing_m` apart in 3D.
struct LayoutTrack {
  int id = 0;
  TrackKind kind = TrackKind::kMain;
  int joins_track = -1;   ///< id of the track a turnout connects it to (auxiliary), else -1
  double offset_m = 0.0;  ///< lateral offset of the parallel part from the main track (+ left)
  double main_chainage_begin_m = 0.0, main_chainage_end_m = 0.0;  ///< main chainage it spans
  std::vector<LayoutBlock> blocks;
  std::vector<OffsetPiece> offset;  ///< y(x) over [main_chainage_begin_m, _end_m]
  std::vector<PolylineRun> runs;    ///< the polyline, in order of main chainage
  /// Along this polyline: stretches inside a turnout connection (closer than the track-centre
  /// distance by design).
  std::vector<std::pair<double, double>> turnout_ranges_m;

  double length_m() const { return runs.empty() ? 0.0 : runs.back().distance_end_m; }
};

/// Polyline points of a layout track with their along-polyline distance and main chainage.
struct Polyline {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> distance_m;
  std::vector<double> main_chainage_m;
};

/// The polyline of `track` (the points of every segment that reaches main chainage
/// [x_begin, x_end]; all of it by default). Points are the track's position at their main
/// chainage (trackFrame), bit for bit the same whichever window asks for them.
Polyline samplePolyline(const Track& main, const LayoutTrack& track,
                        double x_begin = -std::numeric_limits<double>::infinity(),
                        double x_end = std::numeric_limits<double>::infinity());

/// Calls visit(point, distance_m, main_chainage_m) for every polyline point in order, holding
/// one run at a time.
void forEachPolylinePoint(const Track& main, const LayoutTrack& track,
                          const std::function<void(const Eigen::Vector3d&, double, double)>& visit);

/// A track along `main` at the lateral offset law `offset` (pieces that tile a stretch of main
/// chainage), sampled at most `spacing_m` apart, one block of `type` per piece. buildLayout
/// lays its tracks this way, with blocks cut at the main blocks as well.
LayoutTrack offsetTrack(const Track& main, int id, TrackKind kind, std::vector<OffsetPiece> offset,
                        double spacing_m, LayoutBlockType type = LayoutBlockType::kStraight);

/// All tracks; tracks[0] is the main track, then the double track (if any), then the
/// auxiliary tracks in the order they were placed. A track's id is its index.
struct Layout {
  std::vector<LayoutTrack> tracks;
};

/// Builds the main track, the optional double track and random auxiliary tracks along `route`
/// (the multi-track generator of the paper, §"Multi-tracks generation"). A pure function of
/// (route, params, seed); random draws come from the stream "layout.auxiliary".
///
/// - Main track: `route.track` sampled at every block boundary and at most
///   `polyline_spacing_m` apart; its blocks are route.blocks.
/// - Double track: the normal offset −d of the main centreline (on the right), z equal to the
///   main z at the same chainage; its blocks mirror the main blocks.
/// - Auxiliary tracks: laid beside straight horizontal elements of the main track (κ = 0),
///   never alongside tunnels, bridges or switches. Left: offset +d, joins the main track.
///   Right: offset −2d joining the double track, or −d joining the main track without one.
///   Each has an entering, a parallel and an outgoing part; each end is independently either a
///   turnout from the neighbouring track (diverging arc R through α, straight diagonal
///   L_s = (d − 2R(1 − cos α)) / sin α, reverse arc R; docs/REFERENCES.md R1.5) or a dead
///   end (a straight of `dead_end_length_m` angled at α away from the neighbouring track and an
///   arc R turning it parallel, so the buffer stop lies outside the parallel part). Auxiliary
///   tracks on the same side keep max(20 m, d) of chainage between them. A candidate that would
///   come closer than d to another track (possible only where the route runs back close to
///   itself) is dropped.
/// - Not implemented: the paper's rule for curved main blocks (an entering/outgoing part made
///   of a single straight leaving the curve on its outer side); stretches beside curves and
///   transitions get no auxiliary tracks.
///
/// Throws ConfigError naming the `layout.*` field for invalid parameters, including a
/// track-centre distance too small for the turnout (L_s < 0) when turnouts can be placed.
Layout buildLayout(const Route& route, const LayoutParams& params, std::uint64_t seed);

/// The frame of `track` at main chainage x, in closed form from the main track and the track's
/// offset law: P(x) = main(x) + y(x) l(x), tangent ∝ (1 − κ y) t + y′ l + (dz/dx) up. Exact on
/// the polyline points (which are P at their main chainage). x is clamped to the track.
TrackFrame trackFrame(const Track& main, const LayoutTrack& track, double main_chainage_m);
/// The frame at a distance along the track's polyline, through the main chainage interpolated
/// between polyline points (one run is sampled to find them).
TrackFrame trackFrameAtDistance(const Track& main, const LayoutTrack& track, double distance_m);

/// A polyline point of an auxiliary track too close to another track.
struct ClearanceIssue {
  int track_id;
  int other_track_id;       ///< the nearest track closer than the limit
  double distance_along_m;  ///< of the point, along track_id's polyline
  double clearance_m;       ///< its 3D distance to other_track_id's polyline
};

/// Every polyline point of an auxiliary track (outside its turnout_ranges_m) closer than
/// `min_distance_m - 1e-6` to any other track's polyline (3D point-to-segment distance), one
/// issue per point, reporting the nearest such track. Empty when the layout is sound. Per
/// auxiliary track, only the runs whose plan bounds come within min_distance_m of it are
/// sampled, into a uniform grid hash over their segments (plan cells >= min_distance_m), so
/// memory does not grow with the route.
std::vector<ClearanceIssue> checkClearance(const Track& main, const Layout& layout,
                                           double min_distance_m);

}  // namespace trainsim::track
