// The environment's costs: generation of a 10 km double-track route (terrain, track assets,
// objects), what a tile costs by part, and streaming along routes of 1, 10 and 100 km (the
// scene's memory and the time to get everything within 120 m of a pose). Ratios are to the
// 1 km route measured in the same run.
//
//   bench_environment [--quick]   (--quick: 1 and 10 km only)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>

#include "bench_world.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/terrain/railway.hpp"

namespace {

using namespace trainsim;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using bench::makeWorld;
using bench::World;

struct Walk {
  std::size_t tiles_made = 0;
  std::size_t peak_bytes = 0;  // the held tiles' own bytes (capacity 4), at their largest
  double peak_at_m = 0.0;      // where along the main track
  double window_ms = 0.0;      // mean time of a 120 m window query once its tiles exist
  double seconds_total = 0.0;
};

// Walks the main track every 20 m, asking for the scene within 120 m, as a LiDAR frame would.
Walk walk(const World& w, double from_m, double to_m) {
  Walk out;
  const auto& env = *w.stage->environment;
  auto stream = env.stream(4);  // a 120 m window touches at most 4 tiles of 1 km
  const auto t0 = Clock::now();
  double query = 0.0;
  int queries = 0;
  for (double x = from_m; x < to_m; x += 20.0) {
    const Eigen::Vector3d p = w.stage->railway->frame(0, x).position;
    stream->window(p, 120.0);  // makes what is missing
    const auto q0 = Clock::now();
    const scene::SceneWindow win = stream->window(p, 120.0);
    std::size_t objects = 0;
    win.forEachObject(p, 120.0, [&](const scene::Object&) { ++objects; });
    query += seconds(q0);
    ++queries;
    if (stream->bytes() > out.peak_bytes) {
      out.peak_bytes = stream->bytes();
      out.peak_at_m = x;
    }
  }
  out.tiles_made = static_cast<std::size_t>(stream->made());
  out.window_ms = 1e3 * query / queries;
  out.seconds_total = seconds(t0);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;

  // 1. A 10 km double-track route: every tile, by part.
  {
    const auto t_plan = Clock::now();
    const World w = makeWorld(10'000.0);
    const double plan_s = seconds(t_plan);
    const auto& env = *w.stage->environment;
    double terrain_s = 0.0, objects_s = 0.0, tile_s = 0.0;
    std::size_t triangles = 0, objects = 0, wires = 0;
    for (const auto& index : env.tiles()) {
      auto t0 = Clock::now();
      env.terrain().sceneTile(index);
      terrain_s += seconds(t0);
      t0 = Clock::now();
      objects += env.objects(index).size();
      objects_s += seconds(t0);
      t0 = Clock::now();
      const auto tile = env.tile(index);
      tile_s += seconds(t0);
      triangles += tile->triangleCount();
      wires += tile->wires.size();
    }
    fmt::print(
        "## Environment of a 10 km double-track route ({} scene tiles of {:.0f} m, {} terrain "
        "tiles "
        "of {} x {} vertices)\n\n",
        env.tiles().size(), env.grid().size_m, env.terrain().tiles().size(),
        env.params().terrain.tile_vertices, env.params().terrain.tile_vertices);
    fmt::print("| part | s | s / tile |\n|---|---|---|\n");
    const double n = static_cast<double>(env.tiles().size());
    fmt::print("| plan (route, layout, motion) + railway index + tile set | {:.2f} | |\n", plan_s);
    fmt::print("| terrain height maps | {:.2f} | {:.3f} |\n", terrain_s, terrain_s / n);
    fmt::print("| object placement (with its terrain) | {:.2f} | {:.3f} |\n", objects_s,
               objects_s / n);
    fmt::print("| whole tiles (terrain, mesh, assets, objects) | {:.2f} | {:.3f} |\n", tile_s,
               tile_s / n);
    fmt::print(
        "\n{} triangles (objects as instances: a prototype counted per use), {} trackside objects, "
        "{} wires\n\n",
        triangles, objects, wires);
  }

  // 2. Terrain simplification: tolerance -> triangles -> max height error -> time.
  {
    const World w = makeWorld(10'000.0);
    const auto& env = *w.stage->environment;
    std::vector<terrain::TerrainTile> tiles;
    for (const auto& index : env.terrain().tiles()) {
      tiles.push_back(env.terrain().tile(index));
      if (tiles.size() == 4)
        break;
    }
    fmt::print(
        "## Terrain simplification (CGAL greedy-insertion TIN), mean of {} tiles of {} x {}\n\n",
        tiles.size(), tiles.front().n, tiles.front().n);
    fmt::print(
        "| tolerance (m) | triangles / tile | x full grid | max height error (m) | ms / tile |\n");
    fmt::print("|---|---|---|---|---|\n");
    double full = 0.0;
    for (const double tol : {0.0, 0.005, 0.02, 0.1, 0.5}) {
      double triangles = 0.0, worst = 0.0;
      const auto t0 = Clock::now();
      for (const auto& t : tiles) {
        const Eigen::Vector3d origin(t.origin.x(), t.origin.y(), t.z0);
        if (tol == 0.0) {
          triangles += static_cast<double>(
              terrain::terrainMesh(t, origin, scene::mat::kGrass).triangles.size());
        } else {
          const auto s = terrain::simplifiedTerrainMesh(t, origin, scene::mat::kGrass, tol);
          triangles += static_cast<double>(s.mesh.triangles.size());
          worst = std::max(worst, s.max_error_m);
        }
      }
      const double ms = 1e3 * seconds(t0) / static_cast<double>(tiles.size());
      triangles /= static_cast<double>(tiles.size());
      if (tol == 0.0)
        full = triangles;
      fmt::print("| {} | {:.0f} | {:.4f} | {:.4f} | {:.0f} |\n",
                 tol == 0.0 ? "0 (full grid)" : fmt::format("{}", tol), triangles, triangles / full,
                 worst, ms);
    }
    fmt::print("\n");
  }

  // 3. Streaming: walking whole routes of growing length with a stream of 4 tiles. The scene's
  // memory follows what lies within reach (a station with four tracks holds twice what open
  // line does), so each route's peak is also compared with the kilometre around it walked
  // alone: a 1 km route with the same worst place, which isolates what streaming adds.
  fmt::print(
      "## Streaming: the scene within 120 m of the train, every 20 m of the whole route\n\n");
  fmt::print(
      "| route | tiles existing | tiles made | walk (s) | peak scene MB | at (m) | that km alone "
      "(MB) | x that km | x generated 1 km | window query (ms) | x 1 km |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|\n");
  Walk base;
  for (const double km : quick ? std::vector<double>{1, 10} : std::vector<double>{1, 10, 100}) {
    const World w = makeWorld(km * 1000.0);
    const double length = w.stage->railway->main().length();
    const Walk r = walk(w, 0.0, length);
    const double from = std::clamp(r.peak_at_m - 500.0, 0.0, std::max(0.0, length - 1000.0));
    const Walk alone = walk(w, from, std::min(length, from + 1000.0));
    if (km == 1)
      base = r;
    fmt::print(
        "| {} km | {} | {} | {:.1f} | {:.1f} | {:.0f} | {:.1f} | {:.2f} | {:.2f} | {:.3f} | {:.2f} "
        "|\n",
        km, w.stage->environment->tiles().size(), r.tiles_made, r.seconds_total, r.peak_bytes / 1e6,
        r.peak_at_m, alone.peak_bytes / 1e6,
        static_cast<double>(r.peak_bytes) / static_cast<double>(alone.peak_bytes),
        static_cast<double>(r.peak_bytes) / static_cast<double>(base.peak_bytes), r.window_ms,
        r.window_ms / base.window_ms);
  }
  return 0;
}
