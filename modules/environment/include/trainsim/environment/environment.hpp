#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/scene/scene.hpp"
#include "trainsim/terrain/railway.hpp"
#include "trainsim/terrain/terrain.hpp"

namespace trainsim::environment {

/// Track assets (sensors-reference.md §5). Lengths in m, relative to the top of rail.
struct AssetParams {
  double gauge_m = 1.435;  ///< between running faces, 14 mm below the running surface
  double rail_inclination = 1.0 / 40.0;
  double sleeper_spacing_m = 0.6;
  double sleeper_length_m = 2.6;
  double sleeper_width_m = 0.26;
  double sleeper_height_m = 0.2;
  double ballast_shoulder_m = 0.45;  ///< beyond the sleeper ends
  double ballast_slope = 1.5;        ///< horizontal per vertical
  bool catenary = true;              ///< masts and wires along the main and double track
  double mast_span_m = 60.0;         ///< longest span; shorter in curves to keep the stagger
  double mast_offset_m = 3.2;        ///< mast face from the outermost track centre
  double mast_height_m = 8.0;
  double contact_height_m = 5.3;  ///< contact wire above the top of rail
  double system_height_m = 1.6;   ///< messenger above the contact wire at the supports
  double stagger_m = 0.3;
  double dropper_spacing_m = 10.0;
  double platform_height_m = 0.76;
  double platform_edge_m = 1.65;  ///< platform edge from the track centre
  double platform_width_m = 4.0;
  double bridge_pier_spacing_m = 30.0;
  double fence_probability = 0.3;  ///< per main block and side
  double fence_offset_m = 5.0;     ///< from the outermost track centre
  double signal_offset_m = 2.6;    ///< signal post from the outermost track centre
  /// Shares of the signals showing caution (yellow), and, on tracks the train does not run on,
  /// stop (red); the rest show proceed (green). The train's own track never shows stop: the
  /// train would pass it at danger.
  double signal_caution = 0.3;
  double signal_stop = 0.3;
};

/// What a colour-light signal shows the approaching train, one lamp lit: a pure function of
/// (seed, the signal's instance id), the same over the whole run.
enum class SignalAspect : std::uint8_t { kProceed, kCaution, kStop };
/// "proceed", "caution" or "stop".
std::string_view signalAspectName(SignalAspect aspect);

/// Density and spacing of one kind of trackside object.
struct ObjectKindParams {
  double density_per_ha = 0.0;
  double min_track_distance_m = 6.0;  ///< footprint edge from the nearest track centre
};

/// One kind of trackside object: adding a kind is one entry in objectKinds().
struct ObjectKind {
  std::string_view name;
  std::string_view description;
  ObjectKindParams defaults;
  double radius_min_m, radius_max_m;  ///< footprint (plan) radius
  int variants;                       ///< prototype meshes made per seed
  /// Builds prototype `variant` with footprint radius 1 m, its foot at the origin; instances
  /// scale it by their radius.
  scene::Mesh (*prototype)(std::uint64_t seed, int variant);
  /// The share of the footprint radius it stands on: its foot is the lowest ground under its
  /// centre and four points that far out (a tree's trunk; all of it for the others).
  double foot_share = 1.0;
};
std::span<const ObjectKind> objectKinds();

/// What stands in the way: obstacle detection's positives.
enum class ObstacleKind { kPerson, kCar, kCow };
inline constexpr EnumName<ObstacleKind> kObstacleKindNames[] = {
    {ObstacleKind::kPerson, "person"}, {ObstacleKind::kCar, "car"}, {ObstacleKind::kCow, "cow"}};
constexpr std::span<const EnumName<ObstacleKind>> enumNames(ObstacleKind) {
  return kObstacleKindNames;
}

/// An obstacle placed by hand on or beside a layout track: a person, a car at a level crossing,
/// a cow. It stands on the highest surface under it (Environment::obstacle).
struct Obstacle {
  ObstacleKind kind = ObstacleKind::kPerson;
  int track = 0;                              ///< layout track id (railroad.json)
  double chainage_m = 0.0;                    ///< main chainage
  double offset_m = 0.0;                      ///< from the track's centre, + left
  double heading_rad = std::numbers::pi / 2;  ///< facing, counter-clockwise from the track
};

struct ObjectParams {
  std::vector<ObjectKindParams> kinds;  ///< one per objectKinds() entry
  double cell_m = 8.0;                  ///< candidate lattice spacing
  std::vector<Obstacle> obstacles;
  ObjectParams();
};

/// Where an obstacle stands (Environment::obstacle).
struct PlacedObstacle {
  scene::InstanceId instance = 0;
  Eigen::Vector3d foot = Eigen::Vector3d::Zero();    ///< world
  Eigen::Vector3d along = Eigen::Vector3d::UnitX();  ///< its track's direction there (world)
  /// How far the surface under its footprint's corners lies above (+) and below (−) the foot,
  /// which is on the surface under its centre: an obstacle across a bed's, a platform's or a
  /// parapet's edge sinks into it or overhangs the step (the environment warns past 0.2 m).
  double above_m = 0.0, below_m = 0.0;
};

/// An obstacle kind's footprint: the plan view of its mesh's bounds in its own axes (x the way
/// it faces, y to its left), m.
Eigen::AlignedBox2d obstacleFootprint(ObstacleKind kind);
/// The corners of `o`'s footprint turned by its heading, relative to where it stands, in its
/// track's axes: (along the track, to its left), m.
std::array<Eigen::Vector2d, 4> obstacleCorners(const Obstacle& o);

/// Why an obstacle cannot stand where it is put: on a track the layout does not have, or at a
/// main chainage its track does not cover (to a micrometre: the route's end is on it); nothing
/// if it can. Such an obstacle is left out of the scene (the plan warns): a layout is drawn per
/// seed, and a list of obstacles should serve every seed's (and a shortened route's) as far as
/// it can.
std::optional<std::string> obstacleOffTheLayout(const track::Layout& layout, const Obstacle& o);
/// The same, and also in a tunnel with its footprint beyond the bore's walls (in the rock of
/// the hill, or of the portal): what obstacleOffTheLayout() says, or why it stands in rock.
std::optional<std::string> obstacleLeftOut(const track::Layout& layout,
                                           const std::vector<track::Block>& blocks,
                                           const terrain::TerrainParams& terrain,
                                           const Obstacle& o);

struct EnvironmentParams {
  terrain::TerrainParams terrain;
  AssetParams assets;
  ObjectParams objects;
};

/// A catenary support of the main or double track: its main chainage and the contact wire's
/// registration (stagger, + left of the track centre), chosen along the whole track so that the
/// wire stays within ±stagger of the track everywhere and is continuous from span to span.
struct CatenarySupport {
  double x_m = 0.0;
  double stagger_m = 0.0;
  bool tunnel = false, bridge = false;
};

/// A placed trackside object, as objects.csv lists it.
struct PlacedObject {
  std::size_t kind = 0;
  int variant = 0;
  Eigen::Vector3d position;
  double radius_m = 0.0, yaw_rad = 0.0;
  scene::InstanceId instance = 0;
};

/// The world along the railway: terrain, track assets and trackside objects, tile by tile. A
/// tile is a pure function of (railway, params, seed, index), made on demand (stream()).
class Environment {
 public:
  Environment(std::shared_ptr<const terrain::Railway> railway, EnvironmentParams params,
              std::uint64_t seed);

  const terrain::Terrain& terrain() const { return terrain_; }
  const terrain::Railway& railway() const { return *railway_; }
  const EnvironmentParams& params() const { return params_; }
  /// The scene's tiles: the terrain's scene grid (terrain tiles split scene_tile_split times per
  /// side), so the tiles within a sensor's reach hold little more than what it can see.
  scene::TileGrid grid() const { return terrain_.sceneGrid(); }
  const std::set<scene::TileIndex>& tiles() const { return terrain_.sceneTiles(); }

  /// Everything in one scene tile.
  std::shared_ptr<const scene::Tile> tile(scene::TileIndex index) const;
  /// The same with the tile's terrain already made (Terrain::sceneTile or cropTile).
  std::shared_ptr<const scene::Tile> tile(scene::TileIndex index,
                                          const terrain::TerrainTile& heights) const;
  /// The trackside objects anchored in a tile (also in tile(), as instances).
  std::vector<PlacedObject> objects(scene::TileIndex index) const;
  /// The same with the tile's terrain already made (its heights set the objects' feet).
  std::vector<PlacedObject> objects(scene::TileIndex index,
                                    const terrain::TerrainTile& heights) const;
  /// How far (plan) a tile's content can reach beyond its square: a catenary span belongs to
  /// the tile of its first support and reaches the next one (mast_span_m on) and its mast
  /// (beyond the outermost track); a house, a platform or a bridge's piece the tile holding its
  /// foot or its start (under 20 m: Scene.ATilesContentReachesAtMostTheOverhangBeyondIt).
  double overhang_m() const;
  /// A stream of tiles over this environment, holding at most `capacity` tiles.
  std::unique_ptr<scene::SceneStream> stream(std::size_t capacity = 16) const;

  /// The materials drawn for this seed.
  scene::MaterialId ballastMaterial() const { return ballast_material_; }
  scene::MaterialId groundMaterial() const { return ground_material_; }
  std::uint64_t seed() const { return seed_; }
  /// The catenary supports of a layout track, in main chainage order (empty without a
  /// catenary): O(route / span) numbers, planned once. An auxiliary track's are the main
  /// track's that lie along it (its wires hang from the same masts).
  const std::vector<CatenarySupport>& supports(int track) const { return supports_.at(track); }
  /// The shared signal (post and head) showing `aspect`: its lamp lit (an emitting material),
  /// the other two lenses dark.
  const std::shared_ptr<const scene::Mesh>& signalPrototype(SignalAspect aspect) const {
    return signals_.at(static_cast<std::size_t>(aspect));
  }
  /// The aspect of the signal with this instance id (AssetParams::signal_caution and
  /// signal_stop); nothing for an id that is no signal's.
  std::optional<SignalAspect> signalAspect(scene::InstanceId instance) const;
  /// The layout track a track asset of this instance id belongs to: a rail, a catenary mast or
  /// wire, a signal. Nothing for anything else, platforms, tunnels, bridges and fences included:
  /// they stand by the line as a whole (their ids carry track 0 whichever track is nearest).
  std::optional<int> trackOf(scene::InstanceId instance) const;
  /// Where objects.obstacles[i] stands: its foot on the highest surface under it (a track's
  /// sleepers within half a sleeper of its centre, the ballast bed's top and shoulder slope
  /// beyond, the terrain further out); nothing when the layout cannot hold it. Worked out once,
  /// when the environment is made: every tile asks about every obstacle.
  const std::optional<PlacedObstacle>& obstacle(std::size_t i) const { return placed_.at(i); }
  /// The shared mesh of an obstacle kind.
  const std::shared_ptr<const scene::Mesh>& obstaclePrototype(ObstacleKind kind) const {
    return obstacles_.at(static_cast<std::size_t>(kind));
  }
  /// The shared prototype of an object kind's variant.
  const std::shared_ptr<const scene::Mesh>& prototype(std::size_t kind, int variant) const;

 private:
  std::optional<PlacedObstacle> placeObstacle(std::size_t i) const;
  /// The highest surface an obstacle can stand on over the point `offset_m` left of track
  /// `track` at main chainage `chainage_m`: a track bed's, a platform's, a bridge deck's or
  /// parapet's, the terrain, or in a tunnel the formation.
  Eigen::Vector3d surfaceUnder(int track, double chainage_m, double offset_m) const;

  std::shared_ptr<const terrain::Railway> railway_;
  EnvironmentParams params_;
  std::uint64_t seed_;
  terrain::Terrain terrain_;
  scene::MaterialId ballast_material_, ground_material_;
  std::vector<std::vector<std::shared_ptr<const scene::Mesh>>> prototypes_;
  std::array<std::shared_ptr<const scene::Mesh>, 3> signals_;    // by SignalAspect
  std::array<std::shared_ptr<const scene::Mesh>, 3> obstacles_;  // by ObstacleKind
  std::vector<std::vector<CatenarySupport>> supports_;           // by layout track
  std::vector<std::optional<PlacedObstacle>> placed_;            // by objects.obstacles entry
  std::optional<GeodeticAnchor> anchor_;  // the Earth the track was laid on, if it was
};

/// The 60E1 rail cross-section as a closed polygon (a, z) in m: a across the rail (positive
/// outward), z from the top of the rail (≤ 0), counter-clockwise seen along the rail; `head`
/// marks the edges (from point i to i + 1) of the running surface and the head's sides.
struct RailProfile {
  std::vector<Eigen::Vector2d> points;
  std::vector<bool> head;
};
const RailProfile& rail60E1();

/// Lateral distance from a rail's axis to its gauge face, 14 mm below the running surface,
/// with the rail inclined by `inclination` (tan of the cant of the rail toward the track).
double gaugeFaceOffset(double inclination);

}  // namespace trainsim::environment
