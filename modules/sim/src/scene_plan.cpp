// `plan --scene`: the environment's terrain tiles, object list and a window as .vtm.
#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "trainsim/core/cancel.hpp"
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
  // Tile by tile, so memory stays that of one tile whatever the route's length.
  io::AtomicFile objects(folder / "objects.csv");
  objects.write("instance,kind,variant,class,x_m,y_m,z_m,radius_m,yaw_rad\n");
  const auto kinds = environment::objectKinds();
  for (const scene::TileIndex& index : env.tiles()) {
    throwIfCancelled();
    const terrain::TerrainTile tile = env.terrain().tile(index);
    terrain::writeHeightPng(tile, terrain_dir / fmt::format("tile_{}_{}.png", index.i, index.j));
    std::string rows;
    for (const environment::PlacedObject& o : env.objects(index, tile))
      rows += fmt::format(
          "{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.4f}\n", o.instance, kinds[o.kind].name,
          o.variant, scene::semanticClass(env.prototype(o.kind, o.variant)->parts.back().cls).name,
          o.position.x(), o.position.y(), o.position.z(), o.radius_m, o.yaw_rad);
    objects.write(rows);
  }
  objects.commit();
  // The window: tiles within 150 m of the main track between the two chainages.
  const auto& main = stage.railway->main();
  const double from = std::clamp(window.from_m, 0.0, main.length());
  const double to = std::clamp(window.to_m, from, main.length());
  auto stream = env.stream(64);
  std::set<scene::TileIndex> wanted;
  for (double x = from;; x = std::min(to, x + 50.0)) {
    const Eigen::Vector3d p = stage.railway->frame(0, x).position;
    for (const auto& t : stream->window(p, 150.0).tiles)
      wanted.insert(t->index);
    if (x >= to)
      break;
  }
  std::vector<std::shared_ptr<const scene::Tile>> tiles;
  for (const auto& index : wanted) {
    tiles.push_back(stream->tile(index));
    // The window's height maps also as VTK image data (Warp By Scalar shows them in 3D).
    const terrain::TerrainTile heights = env.terrain().tile(index);
    scene::writeHeightVti(terrain_dir / fmt::format("tile_{}_{}.vti", index.i, index.j), heights.n,
                          heights.origin, heights.spacing_m, heights.heights);
  }
  const Eigen::Vector3d origin = stage.railway->frame(0, from).position;
  scene::writeVtm(tiles, folder / "scene.vtm", origin);
  logInfo(fmt::format("scene: {} terrain tiles, scene.vtm with {} tiles (chainage {:.0f}-{:.0f} m)",
                      env.tiles().size(), tiles.size(), from, to));
}

}  // namespace trainsim::sim
