// The scene: the class and material tables, parts, instances, streaming windows, a railway
// 1000 km out, and the VTK export read back by VTK's own reader.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>
#include <set>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLMultiBlockDataReader.h>

#include "trainsim/scene/export.hpp"

#include "unit/environment_world.hpp"

namespace trainsim {
namespace {

using scenario::Json;

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
                                                            {scene::cls::kSky, "sky"},
                                                            {scene::cls::kPerson, "person"},
                                                            {scene::cls::kCar, "car"},
                                                            {scene::cls::kAnimal, "animal"}};
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
      {scene::mat::kRetroreflector, "retroreflector"},
      {scene::mat::kSignalLensRed, "signal_lens_red"},
      {scene::mat::kSignalLensYellow, "signal_lens_yellow"},
      {scene::mat::kSignalLensGreen, "signal_lens_green"},
      {scene::mat::kSignalLampRed, "signal_lamp_red"},
      {scene::mat::kSignalLampYellow, "signal_lamp_yellow"},
      {scene::mat::kSignalLampGreen, "signal_lamp_green"},
      {scene::mat::kClothing, "clothing"},
      {scene::mat::kSkin, "skin"},
      {scene::mat::kCarPaint, "car_paint"},
      {scene::mat::kGlass, "glass"},
      {scene::mat::kRubber, "rubber"},
      {scene::mat::kHide, "hide"}};
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
  // A window holds exactly the tiles whose square or content comes within its radius (a span
  // whose first support lies in a tile beyond it can reach in), against every tile's bounds;
  // the stream holds its capacity, or twice the tiles a window looks at (within the overhang).
  const World& w = defaultWorld();
  auto stream = w.env().stream(9);
  const scene::TileGrid grid = w.env().grid();
  const double overhang = w.env().overhang_m();
  std::size_t looked_at = 0, reached_in = 0;
  const auto& main = w.railway().main();
  for (double x = 0.0; x < main.length(); x += 100.0) {
    const Eigen::Vector3d p = w.railway().frame(0, x).position;
    const Eigen::Vector2d c = p.head<2>();
    const scene::SceneWindow win = stream->window(p, 120.0);
    EXPECT_FALSE(win.tiles.empty());
    std::set<scene::TileIndex> in_window, expected;
    for (const auto& t : win.tiles)
      in_window.insert(t->index);
    std::size_t candidates = 0;
    for (const auto& t : allTiles()) {
      candidates += grid.distance(t->index, c) <= 120.0 + overhang;
      if (grid.distance(t->index, c) <= 120.0 || t->bounds.planDistance(c) <= 120.0)
        expected.insert(t->index);
      reached_in += grid.distance(t->index, c) > 120.0 && t->bounds.planDistance(c) <= 120.0;
    }
    EXPECT_EQ(in_window, expected) << "at " << x << " m";
    looked_at = std::max(looked_at, candidates);
    EXPECT_LE(stream->cached(), std::max<std::size_t>(9, 2 * looked_at));
    std::size_t near = 0;
    win.forEachObject(p, 120.0, [&](const scene::Object& o) {
      EXPECT_LE(o.bounds.planDistance(p.head<2>()), 120.0);
      ++near;
    });
    EXPECT_GT(near, 0u);
  }
  EXPECT_GT(reached_in, 0u);      // there are such tiles
  EXPECT_GT(stream->made(), 30);  // tiles were dropped and made along the way
}

TEST(Scene, ATilesLevelFrameIsTheEarthsLocalLevelAtItsOrigin) {
  // The tile's level frame (what a ray caster builds its BVH in) comes from GeographicLib at the
  // tile's origin; the reference is the track's own local up, integrated along the ellipsoid by
  // EarthPlacement, at a track point in the tile (the two differ by the curvature between
  // them: at most a tile's diagonal over the Earth's radius, 3e-5 rad).
  const World& w = defaultWorld();
  auto stream = w.env().stream(4);
  const auto& main = w.railway().main();
  ASSERT_NE(main.earth(), nullptr);
  double farthest_tilt = 0.0;
  for (double x = 0.0; x < main.length(); x += 250.0) {
    const track::EarthPlacement::Point e = main.earth()->at(main.horizontal(), main.vertical(), x);
    const Eigen::Vector3d p = w.railway().frame(0, x).position;
    const auto tile = stream->tile(w.env().grid().tileAt(p.x(), p.y()));
    ASSERT_NE(tile, nullptr) << x;
    const Eigen::Matrix3d& level = tile->level;
    EXPECT_LT((level.transpose() * level - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(level.determinant(), 1.0, 1e-12);
    EXPECT_LT(std::acos(std::min(1.0, level.col(2).dot(e.up))), 4e-5) << x;
    farthest_tilt = std::max(farthest_tilt, std::acos(level(2, 2)));
  }
  // 6 km out the ground is tilted 0.9 mrad against the world's axes.
  EXPECT_NEAR(farthest_tilt, main.length() / 6.371e6, 2e-4);
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
  EXPECT_GT(vertices, 20000u);
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

TEST(Scene, ATilesContentReachesAtMostTheOverhangBeyondIt) {
  // Environment::overhang_m bounds how far an object or a wire reaches beyond its tile's square
  // (a window looks that much farther for them): in the default world (128 m tiles), and with
  // the longest spans and the farthest masts the schema allows.
  const auto check = [](const World& w, const std::vector<std::shared_ptr<const scene::Tile>>& all,
                        double at_least) {
    const scene::TileGrid grid = w.env().grid();
    const double overhang = w.env().overhang_m();
    double worst = 0.0;
    const auto beyond = [&](scene::TileIndex t, const scene::Box3d& b) {
      const Eigen::Vector2d lo = grid.corner(t);
      return std::max({lo.x() - b.min.x(), lo.y() - b.min.y(), b.max.x() - (lo.x() + grid.size_m),
                       b.max.y() - (lo.y() + grid.size_m), 0.0});
    };
    for (const auto& tile : all) {
      for (const auto& o : tile->objects)
        worst = std::max(worst, beyond(tile->index, o.bounds));
      for (const auto& wire : tile->wires) {
        scene::Box3d b;
        for (const auto& p : wire.points)
          b.extend(tile->origin + p.cast<double>());
        worst = std::max(worst, beyond(tile->index, b));
      }
      EXPECT_LE(beyond(tile->index, tile->bounds), overhang)
          << tile->index.i << " " << tile->index.j;
    }
    EXPECT_LE(worst, overhang);
    EXPECT_GE(worst, at_least);  // the spans do reach into the next tile
  };
  check(defaultWorld(), allTiles(), 50.0);
  const World far = makeWorld(
      {{"assets", {{"mast_span_m", 100.0}, {"mast_offset_m", 10.0}, {"fence_offset_m", 12.0}}},
       {"route", {{"generator", {{"length_m", 2500.0}}}}}});
  std::vector<std::shared_ptr<const scene::Tile>> tiles;
  for (const auto& i : far.env().tiles())
    tiles.push_back(far.env().tile(i));
  check(far, tiles, 80.0);
}

}  // namespace
}  // namespace trainsim
