// The environment against independent references: the terrain's rules recomputed by brute force
// over every track segment, the rail gauge measured on the meshes, object footprints checked
// pairwise, the catenary against the track frames, determinism across tile orders and threads,
// a far-away copy of the railway, and the VTK export read back by VTK's own reader.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <numeric>
#include <thread>

#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLMultiBlockDataReader.h>

#include "trainsim/core/random.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/scene/export.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim {
namespace {

using scenario::Json;

struct World {
  scenario::Scenario scenario;
  std::unique_ptr<sim::Plan> plan;
  std::shared_ptr<const sim::EnvironmentStage> stage;
  const environment::Environment& env() const { return *stage->environment; }
  const terrain::Railway& railway() const { return *stage->railway; }
};

// The default scenario (station, bridge, two tunnels, double and auxiliary track) with small
// tiles so the tests stay quick, and `patch` merged in.
World makeWorld(const Json& patch = Json::object()) {
  Json input = Json::parse(sim::defaultScenarioText());
  input["terrain"]["tile_vertices"] = 257;
  input.merge_patch(patch);
  World w{sim::resolveScenario(input, "", "test"), nullptr, nullptr};
  w.plan = sim::makePlan(w.scenario);
  w.stage = sim::makeEnvironment(*w.plan, w.scenario);
  return w;
}

const World& defaultWorld() {
  static const World world = makeWorld();
  return world;
}

// Every segment of every track, sampled whole: the brute-force reference.
struct Segment {
  Eigen::Vector3d a, b;
  int track;
  track::LayoutBlockType type;
};
std::vector<Segment> allSegments(const World& w) {
  std::vector<Segment> out;
  for (const auto& t : w.railway().layout().tracks) {
    const track::Polyline line = track::samplePolyline(w.railway().main(), t);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k)
      out.push_back(
          {line.points[k], line.points[k + 1], t.id,
           w.railway().typeAt(t.id, 0.5 * (line.distance_m[k] + line.distance_m[k + 1]))});
  }
  return out;
}

struct Nearest {
  double d = std::numeric_limits<double>::infinity();
  double z = 0.0;
  track::LayoutBlockType type{};
};
Nearest nearest(const std::vector<Segment>& segments, const Eigen::Vector2d& p, bool tunnels) {
  Nearest n;
  for (const Segment& s : segments) {
    if ((s.type == track::LayoutBlockType::kTunnel) != tunnels)
      continue;
    const Eigen::Vector2d u = s.b.head<2>() - s.a.head<2>();
    const double t = std::clamp((p - s.a.head<2>()).dot(u) / u.squaredNorm(), 0.0, 1.0);
    const double d = (p - s.a.head<2>() - t * u).norm();
    if (d < n.d)
      n = {d, s.a.z() + t * (s.b.z() - s.a.z()), s.type};
  }
  return n;
}

// Value noise as the terrain's docs define it, written again from the random stream.
double referenceNoise(const terrain::TerrainParams& P, std::uint64_t seed, double x, double y) {
  const RandomStream stream(seed, "terrain/noise");
  double norm = 0.0, sum = 0.0;
  for (int o = 0; o < P.octaves; ++o)
    norm += std::pow(P.persistence, o);
  for (int o = 0; o < P.octaves; ++o) {
    const double wl = P.wavelength_m / std::pow(2.0, o);
    const double u = x / wl, v = y / wl;
    const double i = std::floor(u), j = std::floor(v);
    const auto node = [&](double a, double b) {
      const std::uint64_t key =
          (static_cast<std::uint64_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(a)))
           << 32) |
          static_cast<std::uint32_t>(static_cast<std::int64_t>(b));
      return 2.0 * stream.uniform4(key, static_cast<std::uint64_t>(o))[0] - 1.0;
    };
    const auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    const double fx = fade(u - i), fy = fade(v - j);
    const double bottom = node(i, j) + fx * (node(i + 1, j) - node(i, j));
    const double top = node(i, j + 1) + fx * (node(i + 1, j + 1) - node(i, j + 1));
    sum += P.amplitude_m * std::pow(P.persistence, o) / norm * (bottom + fy * (top - bottom));
  }
  return sum;
}

TEST(SemanticTable, NamedIdsMatchTheTable) {
  const std::pair<scene::ClassId, const char*> classes[] = {{scene::cls::kUnlabelled, "unlabelled"},
                                                            {scene::cls::kRail, "rail"},
                                                            {scene::cls::kSleeper, "sleeper"},
                                                            {scene::cls::kTrackbed, "trackbed"},
                                                            {scene::cls::kTerrain, "terrain"},
                                                            {scene::cls::kVegetation, "vegetation"},
                                                            {scene::cls::kTree, "tree"},
                                                            {scene::cls::kTrunk, "trunk"},
                                                            {scene::cls::kRock, "rock"},
                                                            {scene::cls::kBuilding, "building"},
                                                            {scene::cls::kPole, "pole"},
                                                            {scene::cls::kWire, "wire"},
                                                            {scene::cls::kFence, "fence"},
                                                            {scene::cls::kPlatform, "platform"},
                                                            {scene::cls::kTunnel, "tunnel"},
                                                            {scene::cls::kBridge, "bridge"},
                                                            {scene::cls::kSignal, "signal"},
                                                            {scene::cls::kSky, "sky"}};
  for (const auto& [id, name] : classes)
    EXPECT_EQ(scene::classId(name), id) << name;
  const std::pair<scene::MaterialId, const char*> materials[] = {
      {scene::mat::kRailHead, "rail_head"},
      {scene::mat::kRailWeb, "rail_web"},
      {scene::mat::kConcrete, "concrete"},
      {scene::mat::kBallastGranite, "ballast_granite"},
      {scene::mat::kBallastBasalt, "ballast_basalt"},
      {scene::mat::kGrass, "grass"},
      {scene::mat::kDryGrass, "dry_grass"},
      {scene::mat::kSoil, "soil"},
      {scene::mat::kLeaves, "leaves"},
      {scene::mat::kNeedles, "needles"},
      {scene::mat::kBark, "bark"},
      {scene::mat::kRock, "rock"},
      {scene::mat::kBrick, "brick"},
      {scene::mat::kPlaster, "plaster"},
      {scene::mat::kRoofTile, "roof_tile"},
      {scene::mat::kGalvanisedSteel, "galvanised_steel"},
      {scene::mat::kCopper, "copper"},
      {scene::mat::kAsphalt, "asphalt"},
      {scene::mat::kPaintedMetal, "painted_metal"},
      {scene::mat::kRetroreflector, "retroreflector"}};
  for (const auto& [id, name] : materials)
    EXPECT_EQ(scene::materialId(name), id) << name;
  for (const auto& m : scene::materials()) {
    EXPECT_GE(m.k_d, 0.0) << m.name;
    EXPECT_GE(m.k_s, 0.0) << m.name;
    EXPECT_GT(m.roughness, 0.0) << m.name;
    EXPECT_LE(m.max_incidence_rad, std::numbers::pi / 2 + 1e-12) << m.name;
    EXPECT_FALSE(m.source.empty()) << m.name;
  }
  // The maps to other taxonomies are the documented ones (sensors-reference.md §4.3).
  EXPECT_EQ(scene::semanticClass(scene::cls::kPole).semantickitti, 80);
  EXPECT_EQ(scene::semanticClass(scene::cls::kTrackbed).railsem19, 15);
  EXPECT_EQ(scene::semanticClass(scene::cls::kSignal).osdar23, "signal");
}

TEST(Terrain, HeightsFollowTheBlendAgainstABruteForceReference) {
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  const terrain::TerrainParams& P = w.env().params().terrain;
  const RandomStream pick(7, "test.terrain.points");
  int near = 0, blend = 0, far = 0;
  for (std::uint64_t k = 0; k < 1500; ++k) {
    // Points along the route, up to 60 m to either side, away from bridges and tunnels.
    const auto u = pick.uniform4(k);
    const double x = u[0] * w.railway().main().length();
    const track::TrackFrame f = w.railway().frame(0, x);
    const Eigen::Vector2d p =
        f.position.head<2>() + (120.0 * u[1] - 60.0) * f.left.head<2>().normalized();
    terrain::HeightParts parts;
    const double h = w.env().terrain().heightAt(p.x(), p.y(), &parts);
    if (parts.valley != 0.0 || std::isfinite(parts.d_tunnel))
      continue;
    const Nearest n = nearest(segments, p, false);
    const double reach = std::max(P.d_far_m, P.d_near_station_m);
    if (n.d <= reach) {
      ASSERT_NEAR(parts.d_open, n.d, 1e-9);
      ASSERT_NEAR(parts.z_open, n.z, 1e-9);
    }
    EXPECT_NEAR(parts.noise, referenceNoise(P, w.scenario.seed(), p.x(), p.y()), 1e-9);
    const double d_near =
        n.type == track::LayoutBlockType::kStation ? P.d_near_station_m : P.d_near_m;
    const double formation = n.z - P.formation_depth_m;
    if (n.d <= d_near) {
      ++near;
      EXPECT_NEAR(h, formation, 1e-9);
    } else if (n.d >= P.d_far_m) {
      ++far;
      EXPECT_NEAR(h, parts.far, 1e-9);
    } else {
      ++blend;
      const double wgt = (n.d - d_near) / (P.d_far_m - d_near);
      EXPECT_NEAR(h, (1 - wgt) * formation + wgt * parts.far, 1e-9);
    }
  }
  EXPECT_GT(near, 50);
  EXPECT_GT(blend, 300);
  EXPECT_GT(far, 300);
}

TEST(Terrain, TheRegionalLevelIsTheWeightedTrackFormation) {
  // Far from the track, height − noise is the inverse-distance weighted formation height of
  // track points every 25 m, bilinear between 25 m lattice nodes: checked at a lattice node.
  const World& w = defaultWorld();
  const terrain::TerrainParams& P = w.env().params().terrain;
  const track::TrackFrame f = w.railway().frame(0, 2400.0);
  const Eigen::Vector2d q = (f.position.head<2>() + 200.0 * f.left.head<2>().normalized()) / 25.0;
  const Eigen::Vector2d node(std::round(q.x()) * 25.0, std::round(q.y()) * 25.0);
  terrain::HeightParts parts;
  w.env().terrain().heightAt(node.x(), node.y(), &parts);
  double sw = 0.0, swz = 0.0;
  for (const auto& t : w.railway().layout().tracks)
    for (double k = std::ceil(t.main_chainage_begin_m / 25.0); k * 25.0 < t.main_chainage_end_m;
         k += 1.0) {
      const Eigen::Vector3d p = w.railway().frame(t.id, k * 25.0).position;
      const double d2 = (p.head<2>() - node).squaredNorm();
      if (d2 >= P.regional_radius_m * P.regional_radius_m)
        continue;
      const double fall = 1.0 - d2 / (P.regional_radius_m * P.regional_radius_m);
      const double wt = fall * fall / (d2 + 625.0);
      sw += wt;
      swz += wt * (p.z() - P.formation_depth_m);
    }
  EXPECT_NEAR(parts.far - parts.noise, swz / sw, 1e-6);
}

TEST(Terrain, ValleysUnderBridgesAndGroundOverTunnels) {
  const World& w = defaultWorld();
  const terrain::TerrainParams& P = w.env().params().terrain;
  int bridges = 0, tunnels = 0;
  for (const terrain::Structure& s : w.railway().structures()) {
    const double inset =
        s.type == track::BlockType::kBridge ? 0.25 * (s.chainage_end_m - s.chainage_begin_m) : 40.0;
    for (double x = s.chainage_begin_m + inset; x <= s.chainage_end_m - inset; x += 10.0)
      for (const double lateral : {-6.0, -2.0, 0.0, 2.0, 6.0}) {
        const track::TrackFrame f = w.railway().frame(0, x);
        const Eigen::Vector2d p = f.position.head<2>() + lateral * f.left.head<2>().normalized();
        const double h = w.env().terrain().heightAt(p.x(), p.y());
        if (s.type == track::BlockType::kBridge) {
          ++bridges;  // room for a river: the ground well below the deck (1.5 m under the
                      // formation)
          EXPECT_LT(h, f.position.z() - P.formation_depth_m - 1.5 - 3.0) << "bridge at " << x;
        } else if (s.type == track::BlockType::kTunnel) {
          ++tunnels;  // the tube (crown tunnel_crown_m above the rails) runs underground
          EXPECT_GE(h, f.position.z() + P.tunnel_crown_m + 0.5 * P.tunnel_cover_m)
              << "tunnel at " << x;
        }
      }
  }
  EXPECT_GT(bridges, 10);
  EXPECT_GT(tunnels, 100);
}

TEST(Terrain, ATileIsTheSameAloneInAnyOrderOnAnyThreadAndAgreesWithItsNeighbours) {
  const World& w = defaultWorld();
  const auto& tiles = w.env().tiles();
  ASSERT_GE(tiles.size(), 4u);
  const scene::TileIndex first = *tiles.begin(), last = *tiles.rbegin();
  const terrain::TerrainTile alone = w.env().terrain().tile(last);
  std::vector<terrain::TerrainTile> in_order;
  for (const auto& t : tiles)
    in_order.push_back(w.env().terrain().tile(t));
  terrain::TerrainTile threaded;
  std::thread([&] { threaded = w.env().terrain().tile(last); }).join();
  for (const auto* other : {&in_order.back(), &threaded}) {
    ASSERT_EQ(other->heights.size(), alone.heights.size());
    EXPECT_EQ(std::memcmp(other->heights.data(), alone.heights.data(),
                          alone.heights.size() * sizeof(double)),
              0);
    EXPECT_EQ(other->z0, alone.z0);
  }
  // Shared borders: a tile's east column is its east neighbour's west column.
  int shared = 0;
  for (const auto& t : in_order)
    for (const auto& u : in_order)
      if (u.index.i == t.index.i + 1 && u.index.j == t.index.j) {
        ++shared;
        for (int r = 0; r < t.n; ++r)
          ASSERT_EQ(t.height(t.n - 1, r), u.height(0, r));
        ASSERT_EQ(t.vertex(t.n - 1, 0), u.vertex(0, 0));
      }
  EXPECT_GT(shared, 0);
  (void)first;
}

TEST(Terrain, HeightPngRoundTrips) {
  const World& w = defaultWorld();
  const terrain::TerrainTile t = w.env().terrain().tile(*w.env().tiles().begin());
  const auto dir = std::filesystem::temp_directory_path() / "trainsim_height_png";
  std::filesystem::create_directories(dir);
  terrain::writeHeightPng(t, dir / "tile.png");
  const io::PngImage png = io::decodePng(io::readFile(dir / "tile.png"));
  const auto meta = Json::parse(io::readFile(dir / "tile.json"));
  ASSERT_EQ(png.depth, 16);
  ASSERT_EQ(png.width, t.n);
  const double scale = meta["scale_m"].get<double>(), z0 = meta["z0_m"].get<double>();
  for (int r = 0; r < t.n; r += 17)
    for (int c = 0; c < t.n; c += 13)
      EXPECT_NEAR(z0 + scale * png.samples16[static_cast<std::size_t>(t.n - 1 - r) * t.n + c],
                  t.height(c, r), 0.5 * scale + 1e-6);
  std::filesystem::remove_all(dir);
}

// All tiles of the default route, made once for the geometry tests.
const std::vector<std::shared_ptr<const scene::Tile>>& allTiles() {
  static const auto tiles = [] {
    std::vector<std::shared_ptr<const scene::Tile>> out;
    for (const auto& i : defaultWorld().env().tiles())
      out.push_back(defaultWorld().env().tile(i));
    return out;
  }();
  return tiles;
}

TEST(Assets, RailsSitAtGaugeAndFollowTheCant) {
  const World& w = defaultWorld();
  const auto& profile = environment::rail60E1().points;
  const std::size_t m = profile.size();
  // The inner corner of the head at 14 mm below the top, before inclination: index of (−36, −14).
  std::size_t corner = m;
  for (std::size_t i = 0; i < m; ++i)
    if (std::abs(profile[i].x() + 0.036) < 1e-9 && std::abs(profile[i].y() + 0.014) < 1e-9)
      corner = i;
  ASSERT_LT(corner, m);
  const track::Polyline main =
      track::samplePolyline(w.railway().main(), w.railway().layout().tracks[0]);
  int checked = 0, canted = 0;
  for (const auto& tile : allTiles()) {
    const scene::Object* left = nullptr;
    const scene::Object* right = nullptr;
    for (const auto& o : tile->objects) {
      if (o.instance == scene::trackAssetInstance(0, 1, 0))
        left = &o;
      if (o.instance == scene::trackAssetInstance(0, 2, 0))
        right = &o;
    }
    if (!left || !right)
      continue;
    // Head part first: both meshes hold the same rings in the same order.
    ASSERT_EQ(left->mesh->vertices.size(), right->mesh->vertices.size());
    for (std::size_t ring = 0; ring * m < left->mesh->vertices.size() / 2; ring += 7) {
      const Eigen::Vector3d a = left->worldVertex(static_cast<std::uint32_t>(ring * m + corner));
      const Eigen::Vector3d b = right->worldVertex(static_cast<std::uint32_t>(ring * m + corner));
      // The inclination moves the corner by (1 − cos β)·36 mm and lifts it < 1 mm: the gauge
      // between the two corners is 1435 mm within 0.5 mm.
      EXPECT_NEAR((a - b).norm(), 1.435, 5e-4);
      // Cant: the line between the rails is tilted by the track's roll at that point.
      const Eigen::Vector3d mid = 0.5 * (a + b);
      std::size_t best = 0;
      for (std::size_t k = 0; k < main.points.size(); ++k)
        if ((main.points[k] - mid).head<2>().squaredNorm() <
            (main.points[best] - mid).head<2>().squaredNorm())
          best = k;
      const track::TrackFrame f = w.railway().frame(0, main.main_chainage_m[best]);
      const double tilt = std::asin((a.z() - b.z()) / (a - b).norm());
      EXPECT_NEAR(tilt, f.roll_rad, 2e-3) << "at chainage " << main.main_chainage_m[best];
      if (std::abs(f.roll_rad) > 0.02)
        ++canted;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(canted, 10);
  EXPECT_NEAR(environment::gaugeFaceOffset(1.0 / 40.0), 0.036, 1e-3);
}

TEST(Assets, ContactWiresHangAtTheContactHeightWithinTheStagger) {
  const World& w = defaultWorld();
  const environment::AssetParams& A = w.env().params().assets;
  std::vector<track::Polyline> lines;
  for (int t = 0; t < 2; ++t)
    lines.push_back(track::samplePolyline(w.railway().main(), w.railway().layout().tracks[t]));
  int spans = 0;
  for (const auto& tile : allTiles())
    for (const auto& wire : tile->wires) {
      if (((wire.instance >> 36) & 0xFF) != 4)
        continue;  // contact wires
      ++spans;
      const int track_id = static_cast<int>((wire.instance >> 44) & 0xFFF);
      for (int s = 0; s <= 8; ++s) {
        const Eigen::Vector3d p =
            tile->origin +
            (wire.points.front() + (wire.points.back() - wire.points.front()) * (s / 8.0f))
                .cast<double>();
        const auto& line = lines[track_id];
        std::size_t best = 0;
        for (std::size_t k = 0; k < line.points.size(); ++k)
          if ((line.points[k] - p).head<2>().squaredNorm() <
              (line.points[best] - p).head<2>().squaredNorm())
            best = k;
        // The frame at the foot of the perpendicular, by bisection on the chainage.
        double lo = line.main_chainage_m[best > 0 ? best - 1 : 0];
        double hi = line.main_chainage_m[std::min(best + 1, line.points.size() - 1)];
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          const track::TrackFrame f = w.railway().frame(track_id, mid);
          ((p - f.position).dot(f.tangent) > 0 ? lo : hi) = mid;
        }
        const track::TrackFrame f = w.railway().frame(track_id, 0.5 * (lo + hi));
        const Eigen::Vector3d r = p - f.position;
        EXPECT_LE(std::abs(r.dot(f.left)), A.stagger_m + 0.01)
            << "track " << track_id << " span " << (wire.instance & 0xFFFFFFFFFull) << " at " << s
            << "/8, chainage " << 0.5 * (lo + hi);
        EXPECT_NEAR(r.dot(f.up), A.contact_height_m, 0.05);
      }
    }
  EXPECT_GT(spans, 150);
  // Continuous from span to span over the whole route, tile borders included: each span starts
  // where the one before it ends.
  std::map<std::pair<int, std::int64_t>, std::pair<Eigen::Vector3d, Eigen::Vector3d>> ends;
  for (const auto& tile : allTiles())
    for (const auto& wire : tile->wires)
      if (((wire.instance >> 36) & 0xFF) == 4)
        ends[{static_cast<int>((wire.instance >> 44) & 0xFFF),
              static_cast<std::int64_t>(wire.instance & 0xFFFFFFFFFull)}] = {
            tile->origin + wire.points.front().cast<double>(),
            tile->origin + wire.points.back().cast<double>()};
  int joints = 0;
  for (auto it = ends.begin(); std::next(it) != ends.end(); ++it) {
    const auto next = std::next(it);
    if (next->first.first != it->first.first || next->first.second != it->first.second + 1)
      continue;
    EXPECT_LT((it->second.second - next->second.first).norm(), 1e-3);
    ++joints;
  }
  EXPECT_GT(joints, 150);
}

TEST(Objects, FootprintsNeverOverlapAndKeepClearOfEveryTrack) {
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  const auto kinds = environment::objectKinds();
  std::vector<environment::PlacedObject> all;
  for (const auto& i : w.env().tiles()) {
    const auto objects = w.env().objects(i);
    all.insert(all.end(), objects.begin(), objects.end());
  }
  ASSERT_GT(all.size(), 500u);
  std::map<std::pair<long, long>, std::vector<std::size_t>> grid;
  for (std::size_t k = 0; k < all.size(); ++k)
    grid[{std::lround(std::floor(all[k].position.x() / 20.0)),
          std::lround(std::floor(all[k].position.y() / 20.0))}]
        .push_back(k);
  std::set<scene::InstanceId> instances;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const auto& o = all[k];
    EXPECT_TRUE(instances.insert(o.instance).second);
    const long gx = std::lround(std::floor(o.position.x() / 20.0)),
               gy = std::lround(std::floor(o.position.y() / 20.0));
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({gx + dx, gy + dy});
        if (it == grid.end())
          continue;
        for (const std::size_t j : it->second) {
          if (j == k)
            continue;
          ASSERT_GE((all[j].position - o.position).head<2>().norm(), all[j].radius_m + o.radius_m)
              << "objects " << k << " and " << j << " overlap";
        }
      }
    // Clear of every track (brute force over all segments, tunnels included), which keeps it
    // off the track bed, platforms, bridge decks, masts and fences (all within 6 m).
    const Nearest open = nearest(segments, o.position.head<2>(), false);
    const Nearest tube = nearest(segments, o.position.head<2>(), true);
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m,
              w.env().params().objects.kinds[o.kind].min_track_distance_m - 1e-9);
    const auto& A = w.env().params().assets;
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m, A.platform_edge_m + A.platform_width_m)
        << kinds[o.kind].name;
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m, A.fence_offset_m) << kinds[o.kind].name;
  }
}

TEST(Objects, PlacementDoesNotDependOnWhichTilesWereMadeFirst) {
  // A tile's objects are decided from candidates around it only: the same tile from a second
  // environment (nothing made before it) and after all others gives the same list.
  const World& w = defaultWorld();
  const World fresh = makeWorld();
  const scene::TileIndex t =
      *std::next(w.env().tiles().begin(), static_cast<long>(w.env().tiles().size() / 2));
  const auto a = w.env().objects(t);
  const auto b = fresh.env().objects(t);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].instance, b[k].instance);
    EXPECT_EQ(a[k].position, b[k].position);
  }
}

TEST(Scene, EveryPartHasAValidClassAndMaterialAndThingsHaveInstances) {
  std::size_t things = 0;
  for (const auto& tile : allTiles()) {
    for (const auto& o : tile->objects) {
      ASSERT_FALSE(o.mesh->parts.empty());
      std::uint32_t covered = 0;
      for (const auto& part : o.mesh->parts) {
        EXPECT_EQ(part.first_triangle, covered);
        covered += part.triangle_count;
        EXPECT_LT(part.cls, scene::classes().size());
        EXPECT_NE(part.cls, scene::cls::kUnlabelled);
        EXPECT_LT(part.material, scene::materials().size());
        EXPECT_NE(part.material, scene::mat::kNone);
        if (scene::semanticClass(part.cls).thing) {
          EXPECT_NE(o.instance, 0u);
          ++things;
        }
      }
      EXPECT_EQ(covered, o.mesh->triangles.size());
    }
    for (const auto& wire : tile->wires) {
      EXPECT_NE(wire.instance, 0u);
      EXPECT_GE(wire.points.size(), 2u);
    }
  }
  EXPECT_GT(things, 1000u);
}

TEST(Scene, AStreamHoldsAtMostItsCapacityAndAWindowOnlyNearTiles) {
  const World& w = defaultWorld();
  auto stream = w.env().stream(3);
  const auto& main = w.railway().main();
  for (double x = 0.0; x < main.length(); x += 100.0) {
    const Eigen::Vector3d p = w.railway().frame(0, x).position;
    const scene::SceneWindow win = stream->window(p, 120.0);
    EXPECT_FALSE(win.tiles.empty());
    for (const auto& t : win.tiles)
      EXPECT_LE(stream->grid().distance(t->index, p.head<2>()), 120.0);
    EXPECT_LE(stream->cached(), 3u);
    std::size_t near = 0;
    win.forEachObject(p, 120.0, [&](const scene::Object& o) {
      EXPECT_LE(o.bounds.planDistance(p.head<2>()), 120.0);
      ++near;
    });
    EXPECT_GT(near, 0u);
  }
}

TEST(Scene, ARailwayAThousandKilometresOutKeepsItsVerticesToAMillimetre) {
  // Noise and objects are keyed by absolute position (so they differ 1000 km away): switched
  // off here, the rest of the scene must come out identical up to the shift.
  const Json patch = {{"terrain", {{"amplitude_m", 0.0}}},
                      {"objects",
                       {{"trees", {{"density_per_ha", 0}}},
                        {"bushes", {{"density_per_ha", 0}}},
                        {"rocks", {{"density_per_ha", 0}}},
                        {"buildings", {{"density_per_ha", 0}}}}}};
  const World w = makeWorld(patch);
  // A whole number of tiles, regional lattice steps and noise wavelengths; and 78 km down, as
  // the ellipsoid is 1000 km out in the anchor's ENU frame.
  const double tile = w.env().grid().size_m;
  const long step = std::lcm(std::lround(tile), 25L);  // whole tiles and regional lattice steps
  const Eigen::Vector3d shift(static_cast<double>((1'000'000 / step + 1) * step), 0.0, -78000.0);
  const auto far_railway = std::make_shared<const terrain::Railway>(w.stage->route->route.route,
                                                                    w.stage->layout->layout, shift);
  const environment::Environment far(far_railway, w.env().params(), w.scenario.seed());
  ASSERT_GT(shift.x(), 1.0e6);
  double worst = 0.0;
  std::size_t vertices = 0;
  for (const double chainage :
       {300.0, 1700.0, 3000.0}) {  // a tunnel portal, the station, the bridge
    const Eigen::Vector3d at = w.railway().frame(0, chainage).position;
    const scene::TileIndex t = w.env().grid().tileAt(at.x(), at.y());
    const scene::TileIndex tf{t.i + static_cast<std::int32_t>(std::lround(shift.x() / tile)), t.j};
    ASSERT_TRUE(far.tiles().contains(tf));
    const auto near_tile = w.env().tile(t);
    const auto far_tile = far.tile(tf);
    ASSERT_EQ(near_tile->objects.size(), far_tile->objects.size());
    for (std::size_t k = 0; k < near_tile->objects.size(); ++k) {
      const auto& a = near_tile->objects[k];
      const auto& b = far_tile->objects[k];
      ASSERT_EQ(a.mesh->vertices.size(), b.mesh->vertices.size());
      for (std::uint32_t v = 0; v < a.mesh->vertices.size(); ++v) {
        worst = std::max(worst, (b.worldVertex(v) - a.worldVertex(v) - shift).norm());
        ++vertices;
      }
    }
    ASSERT_EQ(near_tile->wires.size(), far_tile->wires.size());
    for (std::size_t k = 0; k < near_tile->wires.size(); ++k)
      for (std::size_t v = 0; v < near_tile->wires[k].points.size(); ++v) {
        const Eigen::Vector3d a = near_tile->origin + near_tile->wires[k].points[v].cast<double>();
        const Eigen::Vector3d b = far_tile->origin + far_tile->wires[k].points[v].cast<double>();
        worst = std::max(worst, (b - a - shift).norm());
      }
  }
  EXPECT_GT(vertices, 100000u);
  EXPECT_LT(worst, 1e-3);
}

TEST(Scene, ParaViewReadsTheExportedMultiblock) {
  const World& w = defaultWorld();
  std::vector<std::shared_ptr<const scene::Tile>> tiles(allTiles().begin(), allTiles().begin() + 2);
  const auto dir = std::filesystem::temp_directory_path() / "trainsim_vtm_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const Eigen::Vector3d origin = w.railway().frame(0, 0.0).position;
  scene::writeVtm(tiles, dir / "scene.vtm", origin);
  vtkNew<vtkXMLMultiBlockDataReader> reader;
  reader->SetFileName((dir / "scene.vtm").string().c_str());
  reader->Update();
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
  ASSERT_NE(blocks, nullptr);
  ASSERT_EQ(blocks->GetNumberOfBlocks(), tiles.size());
  for (unsigned b = 0; b < blocks->GetNumberOfBlocks(); ++b) {
    auto* data = vtkPolyData::SafeDownCast(blocks->GetBlock(b));
    ASSERT_NE(data, nullptr);
    std::size_t triangles = 0;
    for (const auto& o : tiles[b]->objects)
      triangles += o.mesh->triangles.size();
    EXPECT_EQ(static_cast<std::size_t>(data->GetNumberOfPolys()), triangles);
    EXPECT_EQ(static_cast<std::size_t>(data->GetNumberOfLines()), tiles[b]->wires.size());
    for (const char* name : {"class", "instance", "material", "radius_m"}) {
      vtkDataArray* array = data->GetCellData()->GetArray(name);
      ASSERT_NE(array, nullptr) << name;
      EXPECT_EQ(array->GetNumberOfTuples(), data->GetNumberOfCells());
    }
    // The first polygon is the terrain's first triangle, class terrain.
    const auto first_poly = data->GetNumberOfLines();
    EXPECT_EQ(data->GetCellData()->GetArray("class")->GetTuple1(first_poly), scene::cls::kTerrain);
    double p[3];
    data->GetPoint(static_cast<vtkIdType>(data->GetNumberOfPoints() - 1), p);
    EXPECT_LT(std::abs(p[0]), 1e4);  // relative to the origin, not world-sized
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace trainsim

namespace trainsim {
namespace {

TEST(Terrain, TheSimplifiedMeshStaysWithinItsToleranceOfEveryGridHeight) {
  // Brute force: every grid point is located in the simplified mesh by scanning all its
  // triangles, and its height compared with the triangle's plane.
  const World w = makeWorld({{"terrain", {{"tile_vertices", 65}}}});
  int tiles = 0;
  for (const auto& index : w.env().tiles()) {
    if (++tiles > 6)
      break;
    const terrain::TerrainTile t = w.env().terrain().tile(index);
    const Eigen::Vector3d origin(t.origin.x(), t.origin.y(), t.z0);
    for (const double tol : {0.02, 0.25}) {
      const terrain::SimplifiedMesh s =
          terrain::simplifiedTerrainMesh(t, origin, scene::mat::kGrass, tol);
      EXPECT_LE(s.max_error_m, tol);
      EXPECT_LT(s.mesh.triangles.size(), 2u * 64 * 64);
      double worst = 0.0;
      for (int r = 0; r < t.n; ++r)
        for (int c = 0; c < t.n; ++c) {
          const Eigen::Vector2d p(c * t.spacing_m, r * t.spacing_m);
          bool found = false;
          for (const auto& tri : s.mesh.triangles) {
            Eigen::Vector3d v[3];
            for (int k = 0; k < 3; ++k)
              v[k] = s.mesh.vertices[tri[k]].cast<double>();
            const double area = (v[1] - v[0]).head<2>().x() * (v[2] - v[0]).head<2>().y() -
                                (v[2] - v[0]).head<2>().x() * (v[1] - v[0]).head<2>().y();
            ASSERT_GT(area, 0.0);  // counter-clockwise from above
            const auto edge = [&](int a, int b) {
              return ((v[b] - v[a]).x() * (p.y() - v[a].y()) -
                      (v[b] - v[a]).y() * (p.x() - v[a].x())) /
                     area;
            };
            const double l0 = edge(1, 2), l1 = edge(2, 0), l2 = edge(0, 1);
            if (l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6)
              continue;
            found = true;
            const double plane = l0 * v[0].z() + l1 * v[1].z() + l2 * v[2].z();
            worst = std::max(worst, std::abs(t.height(c, r) - t.z0 - plane));
            break;
          }
          ASSERT_TRUE(found) << "grid point " << c << ", " << r << " outside the mesh";
        }
      EXPECT_LE(worst, tol + 1e-4);  // float vertices
    }
  }
}

}  // namespace
}  // namespace trainsim

namespace trainsim {
namespace {

TEST(Assets, MastsSignalsAndFencesStayOutOfEveryTracksClearanceGauge) {
  // Below the top of the kinematic gauge (4.35 m above the rails, UIC GB), nothing of a mast,
  // signal or fence comes closer than 2.2 m (plan) to any track centre: the gauge's half-width
  // of about 1.7 m and a margin. The cantilevers reach over the track above it.
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  std::map<std::pair<long, long>, std::vector<const Segment*>> grid;
  for (const auto& s : segments) {
    const Eigen::Vector2d m = 0.5 * (s.a + s.b).head<2>();
    grid[{std::lround(std::floor(m.x() / 20.0)), std::lround(std::floor(m.y() / 20.0))}].push_back(
        &s);
  }
  std::size_t checked = 0;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      if (scene::instanceSource(o.instance) != scene::InstanceSource::kTrackAsset)
        continue;
      const int kind = static_cast<int>((o.instance >> 36) & 0xFF);
      if (kind != 3 && kind != 11 && kind != 12)
        continue;  // masts, fences, signals
      for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
        const Eigen::Vector3d p = o.worldVertex(v);
        double best = std::numeric_limits<double>::infinity(), z = 0.0;
        const long gx = std::lround(std::floor(p.x() / 20.0)),
                   gy = std::lround(std::floor(p.y() / 20.0));
        for (long dx = -1; dx <= 1; ++dx)
          for (long dy = -1; dy <= 1; ++dy) {
            const auto it = grid.find({gx + dx, gy + dy});
            if (it == grid.end())
              continue;
            for (const Segment* s : it->second) {
              const Eigen::Vector2d u = (s->b - s->a).head<2>();
              const double t =
                  std::clamp((p.head<2>() - s->a.head<2>()).dot(u) / u.squaredNorm(), 0.0, 1.0);
              const double d = (p.head<2>() - s->a.head<2>() - t * u).norm();
              if (d < best) {
                best = d;
                z = s->a.z() + t * (s->b.z() - s->a.z());
              }
            }
          }
        if (p.z() > z + 4.35)
          continue;
        ++checked;
        ASSERT_GE(best, 2.2) << "asset kind " << kind << " at " << p.transpose();
      }
    }
  EXPECT_GT(checked, 10000u);
}

}  // namespace
}  // namespace trainsim
