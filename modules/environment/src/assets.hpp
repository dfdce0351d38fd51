// Private to the environment module: the track-asset builders behind Environment::tile().
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/environment/environment.hpp"

namespace trainsim::environment::detail {

/// The kinds of track asset in instance ids (scene::trackAssetInstance).
enum AssetKind : int {
  kRailLeft = 1,
  kRailRight = 2,
  kMast = 3,
  kContactWire = 4,
  kMessenger = 5,
  kDropper = 6,
  kPlatformLeft = 7,
  kPlatformRight = 8,
  kTunnel = 9,
  kBridge = 10,
  kFence = 11,
  kSignal = 12,
  kObstacle = 13
};

/// The sleepers' tops below the top of rail: the 60E1 rail's 172 mm and 10 mm of rail pad and
/// plate.
inline constexpr double kSleeperTopDepth_m = 0.172 + 0.010;

/// Added to a signal's index (its block's id) when it governs the trains running against the
/// main chainage.
inline constexpr std::int64_t kSignalAgainst = std::int64_t{1} << 32;

/// A point of a track's polyline with its frame (world, shifted).
struct FramePoint {
  Eigen::Vector3d position;
  Eigen::Vector3d tangent, left, up;
  double distance_m = 0.0, main_chainage_m = 0.0;
};

/// Everything a builder needs about the tile it fills.
struct TileContext {
  const Environment& env;
  scene::TileIndex index;
  Eigen::Vector2d lo, hi;  ///< the tile's square
  Eigen::Vector3d origin;  ///< the tile's local origin
  scene::Tile& tile;

  bool owns(const Eigen::Vector3d& p) const {
    return p.x() >= lo.x() && p.x() < hi.x() && p.y() >= lo.y() && p.y() < hi.y();
  }
  Eigen::Vector3f local(const Eigen::Vector3d& p) const { return (p - origin).cast<float>(); }

  // What stands upright (masts, posts, signals, piers, trees) stands along the local vertical,
  // the Earth's up at the tile (Tile::level), not along world z: world z is up only at the
  // scenario's origin, and the Earth's curvature tilts them apart by a milliradian every 6.4 km
  // (9° 1000 km out).
  /// The local vertical (world axes).
  Eigen::Vector3d up() const { return tile.level.col(2); }
  /// v's horizontal part, unit.
  Eigen::Vector3d horizontal(const Eigen::Vector3d& v) const {
    const Eigen::Vector3d u = up();
    return (v - v.dot(u) * u).normalized();
  }
  /// How far p lies above q along the vertical.
  double heightOver(const Eigen::Vector3d& p, const Eigen::Vector3d& q) const {
    return (p - q).dot(up());
  }
  /// The ground at p's plan position: the terrain where world (x, y) is p's.
  Eigen::Vector3d ground(const Eigen::Vector3d& p) const;
  /// Upright axes facing along `direction` (its horizontal part): x ahead, z up, right-handed.
  Eigen::Matrix3d upright(const Eigen::Vector3d& direction) const {
    Eigen::Matrix3d axes;
    axes.col(0) = horizontal(direction);
    axes.col(2) = up();
    axes.col(1) = axes.col(2).cross(axes.col(0));
    return axes;
  }
};

/// Runs of consecutive polyline points of `track` whose segments this tile owns (a segment
/// belongs to the tile holding its midpoint), limited to main chainage [x0, x1], with frames.
/// With `reach_m` > 0, every segment that comes within reach_m of the tile's square instead:
/// for what is placed along the track and owned by its own position (sleepers), which may lie
/// in this tile on a segment whose midpoint lies in the next.
std::vector<std::vector<FramePoint>> ownedRuns(const TileContext& ctx, int track, double x0,
                                               double x1, double reach_m = 0.0);

/// Extrudes a cross-section (l, u) along a run of frames into `mesh` (part already begun). A
/// closed profile is oriented automatically; an open one must have the outside on the right of
/// its direction of travel, seen with the track coming toward the viewer. `part_of_edge`
/// (optional) picks the part index of each profile edge among `parts`.
/// Profile points flagged in `level` (optional) are placed across the local horizontal and along
/// the local vertical instead of the track's canted frame: what meets the level ground.
void extrude(scene::Mesh& mesh, const TileContext& ctx, const std::vector<FramePoint>& run,
             const std::vector<Eigen::Vector2d>& profile, bool closed,
             const std::vector<bool>* level = nullptr);

/// The main-track chainage ranges, sorted and disjoint, where a track of the layout (`track`,
/// or any with -1) passes within `reach` of the tile (plan view): what stands at most `reach`
/// beside a track and is in the tile has its chainage in one of them.
std::vector<std::pair<double, double>> mainChainagesNear(const TileContext& ctx, double reach,
                                                         int track = -1);
/// Whether [x0, x1] meets one of `ranges` (sorted and disjoint).
bool overlaps(const std::vector<std::pair<double, double>>& ranges, double x0, double x1);

/// Outermost track offsets (as outermostOffsets) over a chainage range, sampled every 10 m.
std::pair<double, double> outermostOver(const track::Layout& layout, double x0, double x1);
/// A horseshoe of radius r around (centre, 0): a half circle of `segments` chords above
/// `spring` and walls down to `floor`, from (centre + r, floor) round to (centre − r, floor).
std::vector<Eigen::Vector2d> horseshoe(double centre, double r, double spring, double floor,
                                       int segments);
/// Chords of a tunnel lining's arc.
constexpr int kTunnelArc = 16;
/// A tunnel's tube: one horseshoe around all its tracks, crown tunnel_crown_m above the rails,
/// in (lateral from the main track, height above the top of rail).
struct TunnelTube {
  double centre = 0.0, r = 0.0, spring = 0.0;
  /// The lining's height over `lateral` (on its chords; the springing beyond them).
  double roof(double lateral) const;
};
/// The tube of the tunnel over main chainages [x0, x1].
TunnelTube tunnelTube(const track::Layout& layout, const terrain::TerrainParams& terrain, double x0,
                      double x1);

/// A track's lateral offset from the main track (+ left) at main chainage x, if it is there.
std::optional<double> trackOffset(const track::LayoutTrack& track, double x);
/// Lateral offsets (from the main track, + left) of the outermost track on each side at main
/// chainage x: left ≥ 0, right ≤ 0.
std::pair<double, double> outermostOffsets(const track::Layout& layout, double x);

/// The catenary supports of a layout track along the whole route: every span of the main and
/// double track; on an auxiliary track, the main track's supports that lie along it, strictly
/// within its ends, cut to the longest run of spans whose chord keeps within the stagger of it
/// (its parallel part), so its wires end at the first and last of those.
std::vector<CatenarySupport> planSupports(const terrain::Railway& railway, const AssetParams& A,
                                          int track);

/// The ballast bed's cross-section in a track's canted (left, up) axes, from the top of rail:
/// the sleepers' half length and top, the bed's top (the crib a little below the sleepers'
/// tops) and its half widths there and at the formation, `formation` below the top of rail.
struct BallastSection {
  double sleeper_half = 0.0, sleeper_top = 0.0, top = 0.0, half_top = 0.0, half_bottom = 0.0;
  double formation = 0.0;
  /// The visible surface at `y` from the track's centre: the sleepers' tops, the bed's top, its
  /// shoulder slope; nothing beyond the toe.
  std::optional<double> heightAt(double y) const;
};
BallastSection ballastSection(const AssetParams& A, double formation);

/// A station's side platform on `side` (+1 left, −1 right of the main track): the stretch of
/// main chainage it is laid along and its front (`edge`) and back offsets from the main track,
/// its top platform_height_m above the top of rail; none where no stretch is long enough.
struct PlatformSpan {
  double x0 = 0.0, x1 = 0.0, edge = 0.0, back = 0.0;
};
std::optional<PlatformSpan> platformSpan(const track::Layout& layout, const AssetParams& A,
                                         const terrain::Structure& station, int side);
/// A bridge's deck between offsets `right` and `left` of the main track, its top at the
/// formation, with a parapet kParapet_m wide along each edge, on the deck, its top 1 m above
/// the top of rail.
struct BridgeDeck {
  double right = 0.0, left = 0.0;
};
constexpr double kParapet_m = 0.3;
BridgeDeck bridgeDeck(const track::Layout& layout, const AssetParams& A,
                      const terrain::Structure& bridge);

void addTrackAssets(TileContext& ctx);
void addCatenary(TileContext& ctx);
void addStructures(TileContext& ctx);
void addFencesAndSignals(TileContext& ctx);

/// The obstacles placed by hand (ObjectParams::obstacles) whose feet lie in the tile.
void addObstacles(TileContext& ctx);

}  // namespace trainsim::environment::detail
