#include "trainsim/environment/environment.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "assets.hpp"
#include "objects.hpp"
#include "trainsim/core/cancel.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/track/earth.hpp"

namespace trainsim::environment {

std::optional<std::string> obstacleOffTheLayout(const track::Layout& layout, const Obstacle& o) {
  if (o.track < 0 || o.track >= static_cast<int>(layout.tracks.size()))
    return fmt::format(
        "the layout has no track {} (it has {}: railroad.json lists them, 0 the "
        "main track)",
        o.track, layout.tracks.size());
  const track::LayoutTrack& t = layout.tracks[static_cast<std::size_t>(o.track)];
  constexpr double kSlack_m = 1e-6;  // a route's end chainage is a sum of its pieces' lengths
  if (!(o.chainage_m >= t.main_chainage_begin_m - kSlack_m &&
        o.chainage_m <= t.main_chainage_end_m + kSlack_m))
    return fmt::format(
        "{:g} m is not on track {}, which runs from main chainage {:.1f} to {:.1f} m", o.chainage_m,
        o.track, t.main_chainage_begin_m, t.main_chainage_end_m);
  return std::nullopt;
}

std::optional<std::string> obstacleLeftOut(const track::Layout& layout,
                                           const std::vector<track::Block>& blocks,
                                           const terrain::TerrainParams& terrain,
                                           const Obstacle& o) {
  if (auto why = obstacleOffTheLayout(layout, o))
    return why;
  const auto tunnel = std::ranges::find_if(blocks, [&](const track::Block& b) {
    return b.type == track::BlockType::kTunnel && o.chainage_m >= b.chainage_begin_m &&
           o.chainage_m <= b.chainage_end_m;
  });
  if (tunnel == blocks.end())
    return std::nullopt;
  // The footprint's corners across the main track (the tracks run parallel enough in a tunnel
  // for the heading to be taken from the main track's direction), against the bore's walls.
  const double centre =
      detail::trackOffset(layout.tracks[static_cast<std::size_t>(o.track)], o.chainage_m)
          .value_or(0.0) +
      o.offset_m;
  const detail::TunnelTube tube =
      detail::tunnelTube(layout, terrain, tunnel->chainage_begin_m, tunnel->chainage_end_m);
  double lo = centre, hi = centre;
  for (const Eigen::Vector2d& c : obstacleCorners(o)) {
    lo = std::min(lo, centre + c.y());
    hi = std::max(hi, centre + c.y());
  }
  if (lo >= tube.centre - tube.r && hi <= tube.centre + tube.r)
    return std::nullopt;
  return fmt::format(
      "in the tunnel from main chainage {:.1f} to {:.1f} m its footprint reaches {:.2f} … {:.2f} "
      "m from the main track's centre, beyond the bore's walls ({:.2f} … {:.2f} m): it would "
      "stand in the rock",
      tunnel->chainage_begin_m, tunnel->chainage_end_m, lo, hi, tube.centre - tube.r,
      tube.centre + tube.r);
}

std::array<Eigen::Vector2d, 4> obstacleCorners(const Obstacle& o) {
  const Eigen::AlignedBox2d footprint = obstacleFootprint(o.kind);
  const double c = std::cos(o.heading_rad), s = std::sin(o.heading_rad);
  std::array<Eigen::Vector2d, 4> out;
  std::size_t i = 0;
  for (const auto corner : {Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
                            Eigen::AlignedBox2d::TopLeft, Eigen::AlignedBox2d::TopRight}) {
    const Eigen::Vector2d k = footprint.corner(corner);
    out[i++] = {k.x() * c - k.y() * s, k.x() * s + k.y() * c};
  }
  return out;
}

Eigen::AlignedBox2d obstacleFootprint(ObstacleKind kind) {
  // The meshes' bounds in plan (Environment's constructor builds them; a test holds the two
  // together): the person's arms, the car's body and the cow's head reach furthest.
  switch (kind) {
    case ObstacleKind::kPerson:
      return {Eigen::Vector2d(-0.12, -0.315), Eigen::Vector2d(0.12, 0.315)};
    case ObstacleKind::kCar:
      return {Eigen::Vector2d(-2.2, -0.9), Eigen::Vector2d(2.2, 0.9)};
    case ObstacleKind::kCow:
      break;
  }
  return {Eigen::Vector2d(-0.8, -0.3), Eigen::Vector2d(1.2, 0.3)};
}

Environment::Environment(std::shared_ptr<const terrain::Railway> railway, EnvironmentParams params,
                         std::uint64_t seed)
    : railway_(railway),
      params_(std::move(params)),
      seed_(seed),
      terrain_(railway, params_.terrain, seed) {
  // Ballast and landscape materials are drawn per seed.
  const RandomStream materials(seed, "environment/materials");
  const auto u = materials.uniform4(0);
  ballast_material_ = u[0] < 0.5 ? scene::mat::kBallastGranite : scene::mat::kBallastBasalt;
  ground_material_ = u[1] < 0.6   ? scene::mat::kGrass
                     : u[1] < 0.9 ? scene::mat::kDryGrass
                                  : scene::mat::kSoil;
  for (const ObjectKind& kind : objectKinds()) {
    prototypes_.emplace_back();
    for (int v = 0; v < kind.variants; ++v) {
      scene::Mesh mesh = kind.prototype(seed, v);
      mesh.prototype = true;
      prototypes_.back().push_back(std::make_shared<const scene::Mesh>(std::move(mesh)));
    }
  }
  // Signals: a post and a head with three lamps, red over yellow over green, on the face the
  // approaching train sees (−x: the signal's x runs along the track, the way the train goes);
  // one prototype per aspect, its lamp lit and the other two lenses dark.
  for (const SignalAspect aspect :
       {SignalAspect::kProceed, SignalAspect::kCaution, SignalAspect::kStop}) {
    auto signal = std::make_shared<scene::Mesh>();
    signal->prototype = true;
    signal->beginPart(scene::cls::kPole, scene::mat::kGalvanisedSteel);
    scene::addCylinder(*signal, {0, 0, -0.3f}, {0, 0, 4.6f}, 0.07f, 0.07f, 8);
    signal->beginPart(scene::cls::kSignal, scene::mat::kPaintedMetal);
    scene::addBox(*signal, {-0.15f, -0.18f, 4.0f}, {0.1f, 0.18f, 5.1f});
    struct Lamp {
      float z;
      SignalAspect shows;
      scene::MaterialId off, on;
    };
    constexpr Lamp kLamps[] = {
        {4.85f, SignalAspect::kStop, scene::mat::kSignalLensRed, scene::mat::kSignalLampRed},
        {4.55f, SignalAspect::kCaution, scene::mat::kSignalLensYellow,
         scene::mat::kSignalLampYellow},
        {4.25f, SignalAspect::kProceed, scene::mat::kSignalLensGreen,
         scene::mat::kSignalLampGreen}};
    for (const Lamp& lamp : kLamps) {
      signal->beginPart(scene::cls::kSignal, lamp.shows == aspect ? lamp.on : lamp.off);
      scene::addCylinder(*signal, {-0.15f, 0.0f, lamp.z}, {-0.19f, 0.0f, lamp.z}, 0.09f, 0.09f, 12);
    }
    signals_[static_cast<std::size_t>(aspect)] = std::move(signal);
  }
  // Obstacles: a person 1.75 m tall, a car 4.4 m long, a cow; x the way each faces, y to its
  // left, z up from its feet.
  {
    using V = Eigen::Vector3f;
    auto person = std::make_shared<scene::Mesh>();
    person->beginPart(scene::cls::kPerson, scene::mat::kClothing);
    for (const float y : {0.1f, -0.1f})  // legs
      scene::addCylinder(*person, V(0, y, 0), V(0, y, 0.87f), 0.075f, 0.065f, 8);
    scene::addBox(*person, V(-0.12f, -0.21f, 0.85f), V(0.12f, 0.21f, 1.46f));  // torso
    for (const float y : {0.26f, -0.26f})                                      // arms
      scene::addCylinder(*person, V(0.02f, y, 0.82f), V(0, y, 1.43f), 0.045f, 0.055f, 8);
    person->beginPart(scene::cls::kPerson, scene::mat::kSkin);
    scene::addCylinder(*person, V(0, 0, 1.45f), V(0, 0, 1.75f), 0.095f, 0.09f, 10);  // head
    auto car = std::make_shared<scene::Mesh>();
    car->beginPart(scene::cls::kCar, scene::mat::kCarPaint);
    scene::addBox(*car, V(-2.2f, -0.88f, 0.3f), V(2.2f, 0.88f, 0.95f));    // body
    scene::addBox(*car, V(-1.05f, -0.78f, 1.38f), V(0.8f, 0.78f, 1.45f));  // roof
    car->beginPart(scene::cls::kCar, scene::mat::kGlass);
    scene::addBox(*car, V(-1.1f, -0.8f, 0.95f), V(0.85f, 0.8f, 1.38f));  // windows
    car->beginPart(scene::cls::kCar, scene::mat::kRubber);
    for (const float x : {1.35f, -1.35f})
      for (const float y : {0.9f, -0.9f})
        scene::addCylinder(*car, V(x, y * 0.75f, 0.32f), V(x, y, 0.32f), 0.32f, 0.32f, 12);
    auto cow = std::make_shared<scene::Mesh>();
    cow->beginPart(scene::cls::kAnimal, scene::mat::kHide);
    scene::addBox(*cow, V(-0.8f, -0.3f, 0.72f), V(0.7f, 0.3f, 1.38f));   // body
    scene::addBox(*cow, V(0.62f, -0.13f, 1.0f), V(1.2f, 0.13f, 1.42f));  // neck and head
    for (const float x : {0.55f, -0.65f})
      for (const float y : {0.2f, -0.2f})
        scene::addCylinder(*cow, V(x, y, 0), V(x, y, 0.76f), 0.065f, 0.075f, 8);
    for (const auto& [kind, mesh] :
         {std::pair{ObstacleKind::kPerson, person}, std::pair{ObstacleKind::kCar, car},
          std::pair{ObstacleKind::kCow, cow}}) {
      mesh->prototype = true;
      obstacles_[static_cast<std::size_t>(kind)] = mesh;
    }
  }
  if (const track::EarthPlacement* earth = railway_->main().earth())
    anchor_.emplace(earth->anchor());
  const auto& tracks = railway_->layout().tracks;
  supports_.resize(tracks.size());
  if (params_.assets.catenary)
    for (const track::LayoutTrack& t : tracks)
      supports_[static_cast<std::size_t>(t.id)] =
          detail::planSupports(*railway_, params_.assets, t.id);
  for (std::size_t i = 0; i < params_.objects.obstacles.size(); ++i)
    placed_.push_back(placeObstacle(i));
}

std::string_view signalAspectName(SignalAspect aspect) {
  switch (aspect) {
    case SignalAspect::kProceed:
      return "proceed";
    case SignalAspect::kCaution:
      return "caution";
    case SignalAspect::kStop:
      return "stop";
  }
  return "";
}

std::optional<SignalAspect> Environment::signalAspect(scene::InstanceId instance) const {
  const std::optional<scene::TrackAsset> asset = scene::trackAsset(instance);
  if (!asset || asset->kind != detail::kSignal)
    return std::nullopt;
  // One uniform per signal, keyed by its instance id: the same wherever and whenever it is made.
  const double u = RandomStream(seed_, "environment/signals").uniform4(instance)[0];
  const AssetParams& a = params_.assets;
  const double stop = asset->track_id == 0 ? 0.0 : a.signal_stop;  // the train runs on track 0
  if (u < stop)
    return SignalAspect::kStop;
  return u < stop + a.signal_caution ? SignalAspect::kCaution : SignalAspect::kProceed;
}

std::optional<int> Environment::trackOf(scene::InstanceId instance) const {
  const std::optional<scene::TrackAsset> asset = scene::trackAsset(instance);
  if (!asset)
    return std::nullopt;
  switch (asset->kind) {
    case detail::kRailLeft:
    case detail::kRailRight:
    case detail::kMast:
    case detail::kContactWire:
    case detail::kMessenger:
    case detail::kDropper:
    case detail::kSignal:
    case detail::kObstacle:
      return asset->track_id;
    default:
      return std::nullopt;
  }
}

const std::shared_ptr<const scene::Mesh>& Environment::prototype(std::size_t kind,
                                                                 int variant) const {
  return prototypes_.at(kind).at(static_cast<std::size_t>(variant));
}

std::vector<PlacedObject> Environment::objects(scene::TileIndex index) const {
  const terrain::TerrainTile heights = terrain_.sceneTile(index);
  return objects(index, heights);
}

std::vector<PlacedObject> Environment::objects(scene::TileIndex index,
                                               const terrain::TerrainTile& heights) const {
  return detail::placeObjects(*this, index, &heights);
}

std::shared_ptr<const scene::Tile> Environment::tile(scene::TileIndex index) const {
  return tile(index, terrain_.sceneTile(index));
}

std::shared_ptr<const scene::Tile> Environment::tile(scene::TileIndex index,
                                                     const terrain::TerrainTile& heights) const {
  auto tile = std::make_shared<scene::Tile>();
  tile->index = index;
  const scene::TileGrid g = grid();
  const Eigen::Vector2d lo = g.corner(index);
  tile->origin = {lo.x(), lo.y(), heights.z0};
  if (anchor_)
    tile->level = anchor_->rotationAnchorFromLocalEnu(tile->origin - railway_->shift());
  // The ground: simplified to its vertical tolerance (CGAL), or the full grid.
  const double tolerance = params_.terrain.simplify_tolerance_m;
  auto ground =
      tolerance > 0.0
          ? terrain::simplifiedTerrainMesh(heights, tile->origin, ground_material_, tolerance).mesh
          : terrain::terrainMesh(heights, tile->origin, ground_material_);
  tile->objects.push_back(
      scene::Object::place(std::make_shared<const scene::Mesh>(std::move(ground)), tile->origin,
                           Eigen::Matrix3f::Identity(), 0));
  detail::TileContext ctx{*this,        index, lo, lo + Eigen::Vector2d::Constant(g.size_m),
                          tile->origin, *tile};
  throwIfCancelled();
  detail::addTrackAssets(ctx);
  detail::addCatenary(ctx);
  detail::addStructures(ctx);
  detail::addFencesAndSignals(ctx);
  detail::addObstacles(ctx);
  throwIfCancelled();
  // Trees, rocks and buildings stand along the local vertical (TileContext::up).
  const Eigen::Matrix3d level = tile->level;
  for (const PlacedObject& o : objects(index, heights)) {
    const Eigen::Matrix3f linear =
        (level * Eigen::AngleAxisd(o.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
         o.radius_m)
            .cast<float>();
    tile->objects.push_back(
        scene::Object::place(prototype(o.kind, o.variant), o.position, linear, o.instance));
  }
  tile->updateBounds();
  return tile;
}

double Environment::overhang_m() const {
  constexpr double kStructures_m = 20.0;
  if (!params_.assets.catenary)
    return kStructures_m;
  // A span's points lie within its length of its first support, its arms and mast within the
  // widest spread of the tracks and the mast's offset beyond it.
  double widest = 0.0;
  for (const track::LayoutTrack& t : railway_->layout().tracks)
    for (const track::OffsetPiece& piece : t.offset)
      widest =
          std::max({widest, std::abs(piece.offset(piece.x0)), std::abs(piece.offset(piece.x1))});
  const AssetParams& A = params_.assets;
  return std::max({kStructures_m, A.mast_span_m + 1.0, 2.0 * widest + A.mast_offset_m + 2.0});
}

std::unique_ptr<scene::SceneStream> Environment::stream(std::size_t capacity) const {
  return std::make_unique<scene::SceneStream>(
      grid(), tiles(), [this](scene::TileIndex i) { return tile(i); }, capacity, overhang_m());
}

}  // namespace trainsim::environment
