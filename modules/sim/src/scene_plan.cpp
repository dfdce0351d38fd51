// `plan --scene`: the environment's terrain tiles, object list and a window as .vtm.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/scene/export.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim::sim {

void writeScene(const EnvironmentStage& stage, const std::filesystem::path& folder,
                const SceneExport& window) {
  namespace fs = std::filesystem;
  const environment::Environment& env = *stage.environment;
  const fs::path terrain_dir = folder / "terrain";
  std::error_code ec;
  fs::create_directories(terrain_dir, ec);
  if (ec)
    throw IoError(fmt::format("{}: cannot create it: {}", terrain_dir.string(), ec.message()));
  // The window: scene tiles within 150 m of the main track between the two chainages.
  const auto& main = stage.railway->main();
  const double from = std::clamp(window.from_m, 0.0, main.length());
  const double to = std::clamp(window.to_m, from, main.length());
  const scene::TileGrid grid = env.grid();
  std::set<scene::TileIndex> wanted;
  for (double x = from;; x = std::min(to, x + 50.0)) {
    const Eigen::Vector2d p = stage.railway->frame(0, x).position.head<2>();
    const scene::TileIndex lo = grid.tileAt(p.x() - 150.0, p.y() - 150.0);
    const scene::TileIndex hi = grid.tileAt(p.x() + 150.0, p.y() + 150.0);
    for (std::int32_t i = lo.i; i <= hi.i; ++i)
      for (std::int32_t j = lo.j; j <= hi.j; ++j)
        if (env.tiles().contains({i, j}) && grid.distance({i, j}, p) <= 150.0)
          wanted.insert({i, j});
    if (x >= to)
      break;
  }
  // Terrain tile by terrain tile, each tile's heights made once and cut into its scene tiles
  // for their objects and, in the window, their scene; memory is one terrain tile's beyond the
  // window's.
  io::AtomicFile objects(folder / "objects.csv");
  objects.write("instance,kind,variant,class,x_m,y_m,z_m,radius_m,yaw_rad\n");
  const auto kinds = environment::objectKinds();
  const int split = env.params().terrain.scene_tile_split;
  std::vector<std::shared_ptr<const scene::Tile>> tiles;
  for (const scene::TileIndex& index : env.terrain().tiles()) {
    throwIfCancelled();
    const terrain::TerrainTile heights = env.terrain().tile(index);
    const std::string stem = fmt::format("tile_{}_{}", index.i, index.j);
    terrain::writeHeightPng(heights, terrain_dir / (stem + ".png"));
    bool in_window = false;
    for (std::int32_t j = index.j * split; j < (index.j + 1) * split; ++j)
      for (std::int32_t i = index.i * split; i < (index.i + 1) * split; ++i) {
        if (!env.tiles().contains({i, j}))
          continue;
        const terrain::TerrainTile part = terrain::cropTile(heights, {i, j}, split);
        std::string rows;
        for (const environment::PlacedObject& o : env.objects({i, j}, part))
          rows += fmt::format(
              "{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.4f}\n", o.instance, kinds[o.kind].name,
              o.variant,
              scene::semanticClass(env.prototype(o.kind, o.variant)->parts.back().cls).name,
              o.position.x(), o.position.y(), o.position.z(), o.radius_m, o.yaw_rad);
        objects.write(rows);
        if (wanted.contains({i, j})) {
          tiles.push_back(env.tile({i, j}, part));
          in_window = true;
        }
      }
    // The window's height maps also as VTK image data (Warp By Scalar shows them in 3D).
    if (in_window)
      scene::writeHeightVti(terrain_dir / (stem + ".vti"), heights.n, heights.origin,
                            heights.spacing_m, heights.heights);
  }
  // The obstacles placed by hand, with their track-asset instance ids (as instances.csv gives
  // them) and their yaw counter-clockwise from world x.
  const std::vector<environment::Obstacle>& obstacles = env.params().objects.obstacles;
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    if (const std::optional<environment::PlacedObstacle>& p = env.obstacle(i)) {
      const Eigen::AlignedBox2d footprint = environment::obstacleFootprint(obstacles[i].kind);
      const double radius =
          std::max(footprint.min().norm(), footprint.max().norm());  // about its foot
      objects.write(fmt::format(
          "{},{},0,{},{:.3f},{:.3f},{:.3f},{:.3f},{:.4f}\n", p->instance, nameOf(obstacles[i].kind),
          scene::semanticClass(env.obstaclePrototype(obstacles[i].kind)->parts.back().cls).name,
          p->foot.x(), p->foot.y(), p->foot.z(), radius,
          std::remainder(std::atan2(p->along.y(), p->along.x()) + obstacles[i].heading_rad,
                         2.0 * std::numbers::pi)));
    }
  objects.commit();
  const Eigen::Vector3d origin = stage.railway->frame(0, from).position;
  scene::writeVtm(tiles, folder / "scene.vtm", origin);
  logInfo(fmt::format(
      "scene: {} terrain tiles, scene.vtm with {} scene tiles (chainage {:.0f}-{:.0f} m)",
      env.terrain().tiles().size(), tiles.size(), from, to));
}

}  // namespace trainsim::sim
