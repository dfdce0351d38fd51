// Obstacles placed by hand (objects.obstacles) in the default world: objects of their own on
// their tracks, standing on the surface the sensors see under them (ballast, platforms, bridge
// decks, the terrain), said to when they straddle an edge, and left out where they cannot
// stand (off their track, in a tunnel's rock).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "unit/environment_world.hpp"

namespace trainsim {
namespace {

using scenario::Json;

TEST(Obstacles, StandWhereTheScenarioPutsThemAsObjectsOfTheirOwn) {
  // A person on the main track's sleepers, a car across the double track, a cow in the field:
  // each one object of its kind's class, on its track (instances.csv's track), its feet on the
  // sleepers' tops or on the ground, facing the way heading_deg says, in one tile only.
  Json patch;
  patch["objects"]["obstacles"] = Json::array(
      {{{"kind", "person"}, {"chainage_m", 300.0}, {"offset_m", 0.2}, {"heading_deg", 180.0}},
       {{"kind", "car"}, {"track", 1}, {"chainage_m", 700.0}, {"offset_m", 0.0}},
       {{"kind", "cow"}, {"chainage_m", 900.0}, {"offset_m", 7.0}, {"heading_deg", 45.0}},
       {{"kind", "car"}, {"track", 9}, {"chainage_m", 300.0}},
       {{"kind", "car"}, {"chainage_m", 9000.0}}});
  const World w = makeWorld(patch);
  const std::vector<environment::Obstacle>& list = w.env().params().objects.obstacles;
  ASSERT_EQ(list.size(), 5u);
  // The last two cannot stand where they are put (no track 9; the route is 6 km): left out.
  EXPECT_EQ(environment::obstacleOffTheLayout(w.railway().layout(), list[3]),
            "the layout has no track 9 (it has 3: railroad.json lists them, 0 the main track)");
  EXPECT_EQ(environment::obstacleOffTheLayout(w.railway().layout(), list[4]),
            "9000 m is not on track 0, which runs from main chainage 0.0 to 6000.0 m");
  const scene::ClassId classes[] = {scene::cls::kPerson, scene::cls::kCar, scene::cls::kAnimal};
  const double heights[] = {1.75, 1.45, 1.42};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_FALSE(environment::obstacleOffTheLayout(w.railway().layout(), list[i])) << i;
    const environment::Obstacle& ob = list[i];
    const track::TrackFrame f = w.railway().frame(ob.track, ob.chainage_m);
    const Eigen::Vector3d over = f.position + ob.offset_m * f.left;
    // The tiles around it: the object is in exactly one of them.
    std::vector<const scene::Object*> found;
    std::vector<std::shared_ptr<const scene::Tile>> tiles;
    const scene::TileGrid grid = w.env().grid();
    const scene::TileIndex at = grid.tileAt(over.x(), over.y());
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        if (w.env().tiles().contains({at.i + di, at.j + dj}))
          tiles.push_back(w.env().tile({at.i + di, at.j + dj}));
    for (const auto& tile : tiles)
      for (const scene::Object& o : tile->objects) {
        const auto asset = scene::trackAsset(o.instance);
        EXPECT_FALSE(asset && asset->kind == 13 && asset->index >= 3);
        if (asset && asset->kind == 13 && asset->index == static_cast<std::int64_t>(i))
          found.push_back(&o);
      }
    ASSERT_EQ(found.size(), 1u) << i;
    const scene::Object& o = *found.front();
    EXPECT_EQ(w.env().trackOf(o.instance), ob.track);
    for (const scene::MeshPart& part : o.mesh->parts)
      EXPECT_EQ(part.cls, classes[i]) << i;
    // Feet: on the sleepers' tops (182 mm under the top of rail) on the track, on the ground
    // off it; as tall as its kind along the local vertical.
    double low = 1e300, high = -1e300;
    const Eigen::Vector3d up = o.linear.col(2).cast<double>();
    for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
      low = std::min(low, (o.worldVertex(v) - over).dot(up));
      high = std::max(high, (o.worldVertex(v) - over).dot(up));
    }
    const double foot = std::abs(ob.offset_m) <= 1.3
                            ? -0.182 * f.up.dot(up)
                            : w.env().terrain().heightAt(over.x(), over.y()) - over.z();
    EXPECT_NEAR(low, foot, 0.01) << i;
    EXPECT_NEAR(high - low, heights[i], 0.01) << i;
    // Its kind's footprint (which the train's stop short of it reads) is the mesh's plan bounds.
    Eigen::AlignedBox2d plan;
    for (const Eigen::Vector3f& v : o.mesh->vertices)
      plan.extend(v.head<2>().cast<double>());
    const Eigen::AlignedBox2d footprint = environment::obstacleFootprint(ob.kind);
    EXPECT_LT((plan.min() - footprint.min()).cwiseAbs().maxCoeff(), 0.01) << i;
    EXPECT_LT((plan.max() - footprint.max()).cwiseAbs().maxCoeff(), 0.01) << i;
    // Facing: the object's x is the track's direction turned by heading_deg about the vertical.
    const Eigen::Vector3d forward = o.linear.col(0).cast<double>();
    const Eigen::Vector3d t = (f.tangent - f.tangent.dot(up) * up).normalized();
    const double heading = std::atan2(up.dot(t.cross(forward)), t.dot(forward));
    EXPECT_NEAR(heading, std::remainder(ob.heading_rad, 2.0 * M_PI), 1e-5) << i;
  }
}

// The tiles of `w`'s scene around xy (its own and the eight about it).
std::vector<std::shared_ptr<const scene::Tile>> tilesAround(const World& w,
                                                            const Eigen::Vector2d& xy) {
  std::vector<std::shared_ptr<const scene::Tile>> out;
  const scene::TileIndex at = w.env().grid().tileAt(xy.x(), xy.y());
  for (int di = -1; di <= 1; ++di)
    for (int dj = -1; dj <= 1; ++dj)
      if (w.env().tiles().contains({at.i + di, at.j + dj}))
        out.push_back(w.env().tile({at.i + di, at.j + dj}));
  return out;
}

// The highest surface of `tiles` of the given classes under xy: its height, interpolated in the
// triangle's plan, and its class (none where no triangle is under xy).
std::optional<std::pair<double, scene::ClassId>> highestUnder(
    const std::vector<std::shared_ptr<const scene::Tile>>& tiles, const Eigen::Vector2d& xy,
    const std::vector<scene::ClassId>& classes) {
  std::optional<std::pair<double, scene::ClassId>> out;
  for (const auto& tile : tiles)
    for (const scene::Object& o : tile->objects)
      for (const scene::MeshPart& part : o.mesh->parts) {
        if (std::ranges::find(classes, part.cls) == classes.end())
          continue;
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             ++t) {
          const auto& tri = o.mesh->triangles[t];
          const Eigen::Vector3d a = o.worldVertex(tri[0]), b = o.worldVertex(tri[1]),
                                c = o.worldVertex(tri[2]);
          // Barycentric coordinates of xy in the triangle's plan.
          const Eigen::Vector2d e1 = (b - a).head<2>(), e2 = (c - a).head<2>();
          const double det = e1.x() * e2.y() - e1.y() * e2.x();
          if (std::abs(det) < 1e-12)
            continue;
          const Eigen::Vector2d d = xy - a.head<2>();
          const double u = (d.x() * e2.y() - d.y() * e2.x()) / det;
          const double v = (e1.x() * d.y() - e1.y() * d.x()) / det;
          if (u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9)
            continue;
          const double z = a.z() + u * (b - a).z() + v * (c - a).z();
          if (!out || z > out->first)
            out = std::pair{z, part.cls};
        }
      }
  return out;
}

TEST(Obstacles, StandOnTheSurfaceTheSensorsSeeUnderThem) {
  // Persons beside the main track: on the ballast's top past the sleepers' ends, on its shoulder
  // slope, between the double track's two beds, past the beds on the ground; on a station's
  // platform and on a bridge's deck beside the ballast. Each foot is checked against the scene's
  // own meshes (the highest ballast, sleeper, terrain, platform or bridge triangle under it,
  // interpolated), not against the placement's own section.
  const std::vector<scene::ClassId> ground = {scene::cls::kTrackbed, scene::cls::kSleeper,
                                              scene::cls::kTerrain, scene::cls::kPlatform,
                                              scene::cls::kBridge};
  // Where the platform and the deck are, found in the default scene: across the middle of the
  // station and of the bridge, the first offset (every 10 cm out from the main track, on the
  // side with the platform, and on the right for the deck) where the highest surface is the
  // structure's, then 1.5 m (the platform) or 0.3 m (the deck) further out.
  const World& plain = defaultWorld();
  const auto found = [&](track::BlockType type, double side, scene::ClassId cls, double in) {
    for (const terrain::Structure& s : plain.railway().structures()) {
      if (s.type != type)
        continue;
      const double x = 0.5 * (s.chainage_begin_m + s.chainage_end_m);
      const track::TrackFrame f = plain.railway().frame(0, x);
      const auto tiles = tilesAround(plain, f.position.head<2>());
      for (double y = 0.0; y < 20.0; y += 0.1) {
        const auto top = highestUnder(tiles, (f.position + side * y * f.left).head<2>(), ground);
        if (top && top->second == cls)
          return std::pair{x, side * (y + in)};
      }
    }
    ADD_FAILURE() << "no structure of that kind found";
    return std::pair{0.0, 0.0};
  };
  std::pair<double, double> platform =
      found(track::BlockType::kStation, 1.0, scene::cls::kPlatform, 1.5);
  if (platform.second == 0.0)
    return;
  const std::pair<double, double> deck =
      found(track::BlockType::kBridge, -1.0, scene::cls::kBridge, 0.3);
  Json patch;
  patch["objects"]["obstacles"] =
      Json::array({{{"chainage_m", 1300.0}, {"offset_m", 1.5}},
                   {{"chainage_m", 1350.0}, {"offset_m", 2.2}},
                   {{"chainage_m", 1400.0}, {"offset_m", -2.0}},
                   {{"chainage_m", 1450.0}, {"offset_m", 3.5}},
                   {{"chainage_m", platform.first}, {"offset_m", platform.second}},
                   {{"chainage_m", deck.first}, {"offset_m", deck.second}},
                   {{"kind", "car"},
                    {"chainage_m", deck.first + 10.0},
                    {"offset_m", deck.second},
                    {"heading_deg", 0.0}}});
  const World w = makeWorld(patch);
  for (std::size_t i = 0; i < 6; ++i) {
    const std::optional<environment::PlacedObstacle>& p = w.env().obstacle(i);
    ASSERT_TRUE(p) << i;
    const auto surface = highestUnder(tilesAround(w, p->foot.head<2>()), p->foot.head<2>(), ground);
    ASSERT_TRUE(surface) << i;
    // The ballast and the structures within 2 cm; the terrain within 5 cm (its mesh is
    // simplified to 2 cm of the height grid, whose own triangles differ from the grid's
    // bilinear heights by a little more).
    EXPECT_NEAR(p->foot.z(), surface->first, i == 3 ? 0.05 : 0.02) << i;
  }
  for (const auto& [i, cls] :
       {std::pair{4, scene::cls::kPlatform}, std::pair{5, scene::cls::kBridge}}) {
    const Eigen::Vector2d xy = w.env().obstacle(static_cast<std::size_t>(i))->foot.head<2>();
    EXPECT_EQ(highestUnder(tilesAround(w, xy), xy, ground)->second, cls) << i;
  }
  // The first three stand on ballast, above the formation the terrain meets beside the bed; the
  // person on the platform platform_height_m above the top of rail, the one on the bridge at
  // the formation, metres above the valley floor under the deck.
  const double rail = w.railway().frame(0, 1300.0).position.z();
  EXPECT_NEAR(w.env().obstacle(0)->foot.z(), rail - 0.212, 0.01);
  const environment::AssetParams& A = w.env().params().assets;
  EXPECT_NEAR(w.env().obstacle(4)->foot.z(),
              w.railway().frame(0, platform.first).position.z() + A.platform_height_m, 0.05);
  const Eigen::Vector3d on_deck = w.env().obstacle(5)->foot;
  EXPECT_GT(on_deck.z() - w.env().terrain().heightAt(on_deck.x(), on_deck.y()), 3.0);
  // Level under their whole footprint but the two on the beds' slopes (the person's 0.24 m
  // across them) and the car on the deck, whose 1.8 m width reaches the ballast bed on one side
  // and past the deck's edge on the other: said in above_m and below_m (and warned of).
  for (const std::size_t i : {0u, 4u, 5u}) {
    EXPECT_LT(w.env().obstacle(i)->above_m, 0.02) << i;
    EXPECT_GT(w.env().obstacle(i)->below_m, -0.02) << i;
  }
  for (const std::size_t i : {1u, 2u})
    EXPECT_LT(w.env().obstacle(i)->above_m - w.env().obstacle(i)->below_m, 0.2) << i;
  EXPECT_GT(w.env().obstacle(6)->above_m, 0.2);
  EXPECT_LT(w.env().obstacle(6)->below_m, -3.0);
}

TEST(Obstacles, InATunnelOnlyWithinItsBore) {
  // The default route's first tunnel: the bore's walls found in the scene's own lining (its
  // vertices below 1 m above the rails across the tunnel's middle), and persons facing across
  // the track (their footprint ±0.12 m across it) 0.2 m inside and outside them. One outside
  // would stand in the rock of the hill: left out, saying why. And the route's end chainage is
  // on the route, though the layout's sum of lengths may fall a hair short of it.
  const World& w = defaultWorld();
  const terrain::TerrainParams& terrain = w.env().params().terrain;
  const std::vector<track::Block>& blocks = w.railway().route().blocks;
  const auto tunnel = std::ranges::find_if(
      blocks, [](const track::Block& b) { return b.type == track::BlockType::kTunnel; });
  ASSERT_NE(tunnel, blocks.end());
  const double x = 0.5 * (tunnel->chainage_begin_m + tunnel->chainage_end_m);
  const track::TrackFrame f = w.railway().frame(0, x);
  double left = -1e300, right = 1e300;
  for (const auto& tile : tilesAround(w, f.position.head<2>()))
    for (const scene::Object& o : tile->objects)
      for (const scene::MeshPart& part : o.mesh->parts) {
        if (part.cls != scene::cls::kTunnel)
          continue;
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             ++t)
          for (const std::uint32_t v : o.mesh->triangles[t]) {
            const Eigen::Vector3d p = o.worldVertex(v) - f.position;
            if (std::abs(p.dot(f.tangent)) < 5.0 && p.dot(f.up) < 1.0) {
              left = std::max(left, p.dot(f.left));
              right = std::min(right, p.dot(f.left));
            }
          }
      }
  ASSERT_GT(left, 2.0);
  ASSERT_LT(right, -2.0);
  const auto person = [&](double offset) {
    environment::Obstacle o;
    o.chainage_m = x;
    o.offset_m = offset;
    return o;
  };
  const auto leftOut = [&](const environment::Obstacle& o) {
    return environment::obstacleLeftOut(w.railway().layout(), blocks, terrain, o);
  };
  EXPECT_FALSE(leftOut(person(left - 0.32))) << left;
  EXPECT_FALSE(leftOut(person(right + 0.32))) << right;
  for (const double offset : {left - 0.08, left + 5.0, right + 0.08}) {
    const auto why = leftOut(person(offset));
    ASSERT_TRUE(why) << offset;
    EXPECT_NE(why->find("it would stand in the rock"), std::string::npos) << *why;
  }
  // A car along the track fits where one across it does not (4.4 m long, 1.8 m wide).
  environment::Obstacle car = person(left - 1.2);
  car.kind = environment::ObstacleKind::kCar;
  car.heading_rad = 0.0;
  EXPECT_FALSE(leftOut(car));
  car.heading_rad = std::numbers::pi / 2;
  EXPECT_TRUE(leftOut(car));
  // As far out before the tunnel, in the open, and at the route's end.
  environment::Obstacle open = person(left + 5.0);
  open.chainage_m = tunnel->chainage_begin_m - 30.0;
  EXPECT_FALSE(leftOut(open));
  environment::Obstacle end = person(3.0);
  end.chainage_m = std::round(w.railway().layout().tracks[0].main_chainage_end_m);
  EXPECT_FALSE(leftOut(end)) << end.chainage_m;
}

}  // namespace
}  // namespace trainsim
