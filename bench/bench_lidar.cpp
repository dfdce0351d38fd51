// The LiDAR's costs on the default scene: a 64 × 2048 frame (uniform pattern, +2° to −24.8°,
// noise and motion distortion on) on 2 threads against Embree's raw traversal of exactly the
// same rays in the same run (ranges only, no labels, normals, intensity or output order), the
// ways rays can be handed to Embree (packets of 8 along a ring or down a column, one by one, a
// stream), the ISA cap, instanced against flattened trees, sub-rays a pulse against wire hits,
// the HDL-64E's beams from their calibrated origins against all from the sensor's, fog,
// terrain as triangles or grids, and frame time and memory 1 km and 100 km along a route.
//
//   bench_lidar [--quick | --profile | --fog | --route [KM]]   (--quick: the default scene only;
//   --profile: one frame of the default scene cast 200 times, alternating with its raw
//   traversal, for a profiler; --fog: the fog's table only; --route: 1 km against 100 km only,
//   or against KM km out)
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include <Eigen/Geometry>

#include "bench_world.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace {

using namespace trainsim;
using bench::Clock;
using bench::median;
using bench::ms;
using bench::percentile;

constexpr int kThreads = 2;
constexpr int kRepeats = 7;
const Eigen::Vector3d kMount(10.0, 0.0, 4.0);  // the default scenario's LiDAR

using bench::makeWorld;
using bench::makeWorldWith;
using bench::World;

Eigen::Isometry3d sensorPose(const sim::Trajectory& trajectory, TimeNs t) {
  const sim::TrajectorySample s = trajectory.at(t);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = s.q_world_body.toRotationMatrix();
  T.translation() = s.p_world + T.linear() * kMount;
  return T;
}

// The sensor's pose over a revolution from t0: interpolated between its two ends (the run's
// own poses are exact at 1 ms knots; this keeps the benchmark about casting).
lidar::PoseAt revolution(const sim::Trajectory& trajectory, TimeNs t0) {
  const Eigen::Isometry3d a = sensorPose(trajectory, t0),
                          b = sensorPose(trajectory, t0 + 100'000'000);
  return [a, b](double t) {
    const double u = t / 0.1;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        Eigen::Quaterniond(a.linear()).slerp(u, Eigen::Quaterniond(b.linear())).toRotationMatrix();
    T.translation() = (1 - u) * a.translation() + u * b.translation();
    return T;
  };
}

lidar::Scanner scanner64x2048() {
  lidar::LidarParams p;
  p.pattern = lidar::uniformPattern(64, 2.0, -24.8, 2048, 10.0);
  p.range_sigma_m = 0.02;
  return lidar::Scanner(p);
}

struct FrameCost {
  double frame_ms = 0.0;  // the whole frame: rays, traversal, labels, intensity, noise, order
  double raw_ms = 0.0;    // Embree's traversal of the same rays in packets of 8
  double single_ms = 0.0, stream_ms = 0.0;
  double by_column_ms = 0.0;  // packets of 8 lasers of one column, 16 columns a task
  std::size_t points = 0;
  std::size_t instances = 0;
};

// Three frames along the default route, 40, 120 and 200 s into the run: each revolution's pose
// and the scene within the LiDAR's reach.
struct RouteFrame {
  lidar::PoseAt pose;
  lidar::RayScene scene;
};
std::vector<RouteFrame> framesAlongTheRoute(const World& w, scene::SceneStream& stream,
                                            lidar::RayWorld& world) {
  std::vector<RouteFrame> out;
  for (const TimeNs t : {40'000'000'000, 120'000'000'000, 200'000'000'000}) {
    lidar::PoseAt pose = revolution(w.plan->trajectory(), t);
    lidar::RayScene scene = world.scene(stream.window(pose(0.05).translation(), 125.0).tiles);
    out.push_back({std::move(pose), std::move(scene)});
  }
  return out;
}

// Raw traversal of `rays` split as the scanner splits them (each ring in runs of
// Scanner::columnsPerTask() columns).
double rawTraversal(tbb::task_arena& arena, const lidar::Scanner& scanner,
                    const lidar::RayScene& scene, const std::vector<lidar::Ray>& rays,
                    lidar::RayScene::Traversal mode) {
  // Kept from call to call, as the frame keeps its memory (one caller at a time).
  static std::vector<float> kept;
  kept.resize(rays.size());
  const std::span<float> ranges(kept);
  const auto W = static_cast<std::size_t>(scanner.params().pattern.columns);
  const auto N = static_cast<std::size_t>(scanner.params().sub_rays);
  const std::size_t per_ring = scanner.tasksPerRing(), columns = scanner.columnsPerTask();
  const auto t0 = Clock::now();
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, rays.size() / (W * N) * per_ring, [&](std::size_t t) {
      const std::size_t ring = t / per_ring, begin = t % per_ring * columns;
      const std::size_t first = (ring * W + begin) * N,
                        n = (std::min(W, begin + columns) - begin) * N;
      scene.traverse(std::span(rays).subspan(first, n), ranges.subspan(first, n), mode);
    });
  });
  return ms(t0);
}

// The same rays column by column (each column's rings in turn, 16 columns a task) in packets
// of 8: how the scanner cast them before its tasks were runs of one ring.
double columnMajorTraversal(tbb::task_arena& arena, const lidar::Scanner& scanner,
                            const lidar::RayScene& scene, const std::vector<lidar::Ray>& rays) {
  const auto W = static_cast<std::size_t>(scanner.params().pattern.columns);
  const auto N = static_cast<std::size_t>(scanner.params().sub_rays);
  const std::size_t rings = rays.size() / (W * N);
  std::vector<lidar::Ray> by_column(rays.size());
  for (std::size_t r = 0; r < rings; ++r)
    for (std::size_t c = 0; c < W; ++c)
      std::copy_n(&rays[(r * W + c) * N], N, &by_column[(c * rings + r) * N]);
  static std::vector<float> kept;
  kept.resize(rays.size());
  const std::span<float> ranges(kept);
  const std::size_t per_task = 16 * rings * N;
  const auto t0 = Clock::now();
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, (rays.size() + per_task - 1) / per_task, 1),
        [&](const auto& t) {
          const std::size_t first = t.begin() * per_task;
          const std::size_t n = std::min(per_task, rays.size() - first);
          scene.traverse(std::span(by_column).subspan(first, n), ranges.subspan(first, n),
                         lidar::RayScene::Traversal::kPacket8);
        });
  });
  return ms(t0);
}

FrameCost measure(tbb::task_arena& arena, const lidar::Scanner& scanner,
                  const lidar::RayScene& scene, const lidar::PoseAt& pose, bool all_modes) {
  const RandomStream random(1, "bench");
  FrameCost c;
  std::vector<double> frame, raw, single, stream, by_column;
  const std::vector<lidar::Ray> rays = scanner.rays(scene, pose);
  lidar::LidarFrame f;  // reused, as the run reuses its frames
  for (int r = 0; r < kRepeats; ++r) {
    auto t0 = Clock::now();
    arena.execute([&] { scanner.scan(scene, pose, random, 0, f); });
    frame.push_back(ms(t0));
    c.points = f.points.size();
    raw.push_back(rawTraversal(arena, scanner, scene, rays, lidar::RayScene::Traversal::kPacket8));
    if (all_modes) {
      single.push_back(
          rawTraversal(arena, scanner, scene, rays, lidar::RayScene::Traversal::kSingle));
      stream.push_back(
          rawTraversal(arena, scanner, scene, rays, lidar::RayScene::Traversal::kStream));
      by_column.push_back(columnMajorTraversal(arena, scanner, scene, rays));
    }
  }
  c.frame_ms = median(frame);
  c.raw_ms = median(raw);
  if (all_modes) {
    c.single_ms = median(single);
    c.stream_ms = median(stream);
    c.by_column_ms = median(by_column);
  }
  c.instances = scene.instanceCount();
  return c;
}

// Frames along a stretch of the main track: every `step_m` from `from_m` to `to_m`.
struct Stretch {
  double frame_ms = 0.0, raw_ms = 0.0;  // means
  double points = 0.0;
  double peak_mb = 0.0;   // scene tiles held + Embree's BVHs, at their largest
  double build_ms = 0.0;  // mean time to get a frame's scene (tiles and BVHs made as needed)
  int frames = 0;

  // From the frames' sums to their means.
  void finish() {
    frame_ms /= frames;
    raw_ms /= frames;
    points /= frames;
    build_ms /= frames;
  }
};

Stretch walk(const World& w, scene::SceneStream& stream, lidar::RayWorld& world,
             tbb::task_arena& arena, const lidar::Scanner& scanner, double from_m, double to_m,
             double step_m, bool all_modes = false, FrameCost* first = nullptr) {
  const sim::Trajectory& trajectory = w.plan->trajectory();
  Stretch s;
  // Times at which the front pivot passes each chainage (the trajectory is monotonic).
  TimeNs t = 0;
  const TimeNs dt = trajectory.samplePeriod();
  for (double x = from_m; x < to_m; x += step_m) {
    while (t < trajectory.endTime() && trajectory.at(t).chainage_m < x)
      t += 10 * dt;
    const lidar::PoseAt pose = revolution(trajectory, t);
    const auto b0 = Clock::now();
    const scene::SceneWindow window = stream.window(pose(0.05).translation(), 125.0);
    const lidar::RayScene scene = world.scene(window.tiles);
    s.build_ms += ms(b0);
    const FrameCost c = measure(arena, scanner, scene, pose, all_modes);
    if (first != nullptr && s.frames == 0)
      *first = c;
    s.frame_ms += c.frame_ms;
    s.raw_ms += c.raw_ms;
    s.points += static_cast<double>(c.points);
    s.peak_mb =
        std::max(s.peak_mb,
                 (static_cast<double>(stream.bytes()) + static_cast<double>(world.bytes())) / 1e6);
    ++s.frames;
  }
  s.finish();
  return s;
}

// Walks the windows and scenes from `from_m` to `to_m` every 100 m without casting: the caches
// (scene tiles and BVHs) in the state a run reaches after driving there. `t` is where the search
// for the trajectory's times starts, and is left at the last.
void warm(const World& w, scene::SceneStream& stream, lidar::RayWorld& world, double from_m,
          double to_m, TimeNs& t) {
  const sim::Trajectory& trajectory = w.plan->trajectory();
  for (double x = from_m; x < to_m; x += 100.0) {
    while (t < trajectory.endTime() && trajectory.at(t).chainage_m < x)
      t += 10 * trajectory.samplePeriod();
    world.scene(stream.window(sensorPose(trajectory, t).translation(), 125.0).tiles);
  }
}

void warm(const World& w, scene::SceneStream& stream, lidar::RayWorld& world, double from_m,
          double to_m) {
  TimeNs t = 0;
  warm(w, stream, world, from_m, to_m, t);
}

void printStretch(const char* name, const Stretch& s, const Stretch& base) {
  fmt::print(
      "| {} | {} | {:.0f} | {:.2f} | {:.2f} | {:.3f} | {:.1f} | {:.1f} | {:.2f} | {:.2f} |\n", name,
      s.frames, s.points, s.frame_ms, s.raw_ms, s.frame_ms / s.raw_ms, s.build_ms, s.peak_mb,
      s.frame_ms / base.frame_ms, s.peak_mb / base.peak_mb);
}

// One 2 km unit of route blocks repeated `units` times (the unit turns left and back right, so
// the route keeps heading east).
scenario::Json periodicRoute(int units) {
  struct Block {
    const char* type;
    double length_m;
    const char* turn;  // curves: "left" or "right"
  };
  constexpr Block kUnit[] = {{"straight", 200, nullptr}, {"curve", 100, "left"},
                             {"station", 250, nullptr},  {"straight", 100, nullptr},
                             {"curve", 100, "right"},    {"straight", 150, nullptr},
                             {"tunnel", 300, nullptr},   {"straight", 120, nullptr},
                             {"bridge", 100, nullptr},   {"straight", 100, nullptr}};
  scenario::Json blocks = scenario::Json::array();
  for (int u = 0; u < units; ++u)
    for (const Block& b : kUnit) {
      scenario::Json j = {{"type", b.type}, {"length_m", b.length_m}};
      if (b.turn != nullptr) {  // 120 m transitions either side of the arc: 340 m in all
        j["direction"] = b.turn;
        j["radius_m"] = 3000.0;
        j["transition_m"] = 120.0;
      }
      blocks.push_back(std::move(j));
    }
  return {{"route", {{"source", "blocks"}, {"blocks", std::move(blocks)}}}};
}

// One run's LiDAR pipeline (its scene stream and Embree world) driven along the route, frame by
// frame, so that two places can be measured in turn.
struct Drive {
  const World& w;
  std::unique_ptr<scene::SceneStream> stream;
  std::unique_ptr<lidar::RayWorld> world = std::make_unique<lidar::RayWorld>();
  TimeNs t = 0;  // the last frame's time (chainage only grows)

  explicit Drive(const World& world_) : w(world_), stream(world_.stage->environment->stream(16)) {}
  // The windows and scenes from `from_m` to `to_m` every 100 m, not cast.
  void warm(double from_m, double to_m) { ::warm(w, *stream, *world, from_m, to_m, t); }
  // The frame at chainage `x_m`, measured and added to `s`.
  void frame(tbb::task_arena& arena, const lidar::Scanner& scanner, double x_m, Stretch& s) {
    const sim::Trajectory& trajectory = w.plan->trajectory();
    while (t < trajectory.endTime() && trajectory.at(t).chainage_m < x_m)
      t += 10 * trajectory.samplePeriod();
    const lidar::PoseAt pose = revolution(trajectory, t);
    const auto b0 = Clock::now();
    const lidar::RayScene scene =
        world->scene(stream->window(pose(0.05).translation(), 125.0).tiles);
    s.build_ms += ms(b0);
    const FrameCost c = measure(arena, scanner, scene, pose, false);
    s.frame_ms += c.frame_ms;
    s.raw_ms += c.raw_ms;
    s.points += static_cast<double>(c.points);
    s.peak_mb = std::max(
        s.peak_mb,
        (static_cast<double>(stream->bytes()) + static_cast<double>(world->bytes())) / 1e6);
    ++s.frames;
  }
};

// Frame time and memory 1 km and `far_km` (100 by default) along a route; with another `far_km`,
// the repeated route only.
void routeLength(tbb::task_arena& arena, const lidar::Scanner& scanner, int far_km = 100) {
  // --- 1 km and 100 km along a 100 km route -----------------------------------------------------
  const auto stretchHeader = [] {
    fmt::print(
        "| stretch | frames | points | frame ms | raw traversal ms | frame / raw | scene build ms "
        "| peak MB (tiles + BVHs) | x first row ms | x first row MB |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n");
  };
  // The same scenery at both ends: one 2 km unit of blocks repeated far_km / 2 times, so km 1-11
  // and the last ten kilometres but one (km 89-99 of 100) hold the same track, curves, stations,
  // tunnels and bridges at the same offsets and differ only in what is drawn at random per tile
  // (terrain relief, trees, the layout's extras); five units at each end average that difference
  // down. Each end has a run's own pipeline (scene stream, Embree world), the far one having driven
  // km 1-11 (on the 100 km route) and the 1.5 km before its stretch, so its caches are in the state
  // a run reaches there; and the two ends are measured frame by frame in turn, so that the
  // machine's drift (10-20 % over minutes on this shared VM) falls on both alike.
  {
    const auto p1 = Clock::now();
    const World w = makeWorldWith(periodicRoute(far_km / 2));
    fmt::print("\n{} km route of a repeated 2 km unit planned in {:.1f} s\n\n", far_km,
               ms(p1) / 1e3);
    const double far_from = 1000.0 * far_km - 11'000.0;  // km 89 of 100
    Drive near(w), far(w);
    near.warm(0.0, 1000.0);
    if (far_km == 100)
      far.warm(0.0, 11'000.0);
    far.warm(far_from - 1500.0, far_from);
    Stretch a, b;
    int k = 0;
    for (double x = 1000.0; x < 11'000.0; x += 100.0, ++k) {
      // Which end goes first alternates too.
      for (const bool first_near : {k % 2 == 0, k % 2 != 0}) {
        if (first_near)
          near.frame(arena, scanner, x, a);
        else
          far.frame(arena, scanner, x + far_from - 1000.0, b);
      }
    }
    a.finish();
    b.finish();
    stretchHeader();
    printStretch("km 1-11", a, a);
    const std::string name =
        fmt::format("km {}-{}{}", far_km - 11, far_km - 1,
                    far_km == 100 ? ", after km 1-11 (the same pipeline's caches)" : "");
    printStretch(name.c_str(), b, a);
  }
  if (far_km != 100)
    return;
  // The default scenario's generated route at 100 km: different scenery at either end.
  const auto p1 = Clock::now();
  const World far = makeWorld(100'000.0);
  fmt::print("\nGenerated 100 km route planned in {:.1f} s\n\n", ms(p1) / 1e3);
  stretchHeader();
  auto stream = far.stage->environment->stream(16);
  lidar::RayWorld world;
  warm(far, *stream, world, 0.0, 1500.0);
  const Stretch near = walk(far, *stream, world, arena, scanner, 1500.0, 2500.0, 50.0);
  printStretch("km 1.5-2.5", near, near);
  warm(far, *stream, world, 97'000.0, 98'500.0);
  const Stretch end = walk(far, *stream, world, arena, scanner, 98'500.0, 99'500.0, 50.0);
  printStretch("km 98.5-99.5, after km 2.5", end, near);
  auto fresh_stream = far.stage->environment->stream(16);
  lidar::RayWorld fresh_world;
  warm(far, *fresh_stream, fresh_world, 97'000.0, 98'500.0);
  const Stretch alone =
      walk(far, *fresh_stream, fresh_world, arena, scanner, 98'500.0, 99'500.0, 50.0);
  printStretch("km 98.5-99.5 alone (fresh caches)", alone, near);
  fmt::print(
      "\nkm 98.5-99.5 after km 2.5 against the same km with fresh caches: frame x{:.3f}, "
      "memory x{:.3f}\n",
      end.frame_ms / alone.frame_ms, end.peak_mb / alone.peak_mb);
}

// The HDL-64E S3 preset detecting a 10 % target out to 50 m (its datasheet's pavement range),
// through fog of falling visibility: what the fog costs a frame (every pulse then goes through
// the one-pulse-at-a-time path, which weighs its echo against the surfaces'), and what it
// leaves of the scene, with the strongest and with the last return.
void fogTable(const World& def, tbb::task_arena& arena, const lidar::Scanner& scanner) {
  fmt::print(
      "\nFog (HDL-64E S3 preset, range_10_percent_m 50; 3 frames along the default route):\n\n"
      "| visibility m | returns | frame ms | x clear | surface points | fog points | surface "
      "points beyond 20 m |\n"
      "|---|---|---|---|---|---|---|\n");
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    const std::vector<RouteFrame> frames = framesAlongTheRoute(def, *stream, world);
    double clear_ms = 0.0;
    for (const auto returns :
         {lidar::LidarParams::Returns::kStrongest, lidar::LidarParams::Returns::kLast})
      for (const double visibility : {0.0, 1000.0, 200.0, 100.0, 50.0}) {
        lidar::LidarParams p = scanner.params();
        p.pattern = lidar::preset("hdl64", 10.0);
        p.range_10_percent_m = 50.0;
        p.returns = returns;
        p.fog.visibility_m = visibility;
        const lidar::Scanner foggy(p);
        double frame_ms = 0.0, surface = 0.0, fog = 0.0, far = 0.0;
        for (const auto& [pose, scene] : frames) {
          const RandomStream random(1, "bench");
          lidar::LidarFrame f;
          std::vector<double> times;
          for (int r = 0; r < kRepeats; ++r) {
            const auto t0 = Clock::now();
            arena.execute([&] { foggy.scan(scene, pose, random, 0, f); });
            times.push_back(ms(t0));
          }
          frame_ms += median(times) / 3.0;
          for (const auto& pt : f.points) {
            (pt.cls == scene::cls::kFog ? fog : surface) += 1.0 / 3.0;
            far += pt.cls != scene::cls::kFog && pt.range_m > 20.0 ? 1.0 / 3.0 : 0.0;
          }
        }
        if (visibility == 0.0 && returns == lidar::LidarParams::Returns::kStrongest)
          clear_ms = frame_ms;
        fmt::print("| {} | {} | {:.2f} | {:.2f} | {:.0f} | {:.0f} | {:.0f} |\n",
                   visibility == 0.0 ? std::string("clear") : fmt::format("{:.0f}", visibility),
                   returns == lidar::LidarParams::Returns::kLast ? "last" : "strongest", frame_ms,
                   frame_ms / clear_ms, surface, fog, far);
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  tbb::task_arena arena(kThreads);
  const lidar::Scanner scanner = scanner64x2048();
  if (argc > 1 && std::strcmp(argv[1], "--route") == 0) {
    routeLength(arena, scanner, argc > 2 ? std::max(20, 2 * (std::atoi(argv[2]) / 2)) : 100);
    return 0;
  }
  if (argc > 1 && std::strcmp(argv[1], "--fog") == 0) {
    fogTable(makeWorld(0.0), arena, scanner);
    return 0;
  }
  if (argc > 1 && std::strcmp(argv[1], "--profile") == 0) {
    // One frame of the default scene cast over and over, for a profiler.
    const World w = makeWorld(0.0);
    auto stream = w.stage->environment->stream(16);
    lidar::RayWorld world;
    const lidar::PoseAt pose = revolution(w.plan->trajectory(), 60'000'000'000);
    const lidar::RayScene scene =
        world.scene(stream->window(pose(0.05).translation(), 125.0).tiles);
    const RandomStream random(1, "bench");
    lidar::LidarFrame f;
    const std::vector<lidar::Ray> rays = scanner.rays(scene, pose);
    // Frames and raw traversals alternate, so that drifts in the machine's speed hit both.
    std::vector<double> frame, raw, labelled, copied;
    std::vector<lidar::RayHit> hits(rays.size());
    // The floor under the frame's own work that memory sets: one copy of its points from one
    // buffer to another, both as cold as the frame finds its own after a raw traversal (the
    // frame writes its points to its slots and moves them into ring order: at least twice this).
    std::vector<lidar::LidarPoint> copy_from, copy_to;
    for (int i = 0; i < 200; ++i) {
      const auto t0 = Clock::now();
      arena.execute([&] { scanner.scan(scene, pose, random, 0, f); });
      frame.push_back(ms(t0));
      raw.push_back(
          rawTraversal(arena, scanner, scene, rays, lidar::RayScene::Traversal::kPacket8));
      // The traversal with the hits' labels and normals, as the frame casts (its part of the
      // frame's extra time).
      const auto t1 = Clock::now();
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), scanner.columnsPerTask()),
                          [&](const auto& r) {
                            scene.intersect(std::span(rays).subspan(r.begin(), r.size()),
                                            std::span(hits).subspan(r.begin(), r.size()));
                          });
      });
      labelled.push_back(ms(t1));
      copy_from.resize(f.points.size());
      copy_to.resize(f.points.size());
      rawTraversal(arena, scanner, scene, rays, lidar::RayScene::Traversal::kPacket8);
      const auto t2 = Clock::now();
      arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, copy_from.size(), 4096), [&](const auto& r) {
              // Bytes, as the ring order moves them (two 16-byte moves).
              std::memcpy(static_cast<void*>(&copy_to[r.begin()]), &copy_from[r.begin()],
                          r.size() * sizeof(lidar::LidarPoint));
            });
      });
      copied.push_back(ms(t2));
    }
    fmt::print(
        "{} points; median of 200: {:.2f} ms a frame, raw traversal {:.2f} ms, ratio {:.3f}; "
        "traversal with labels {:.2f} ms ({:.3f} x raw); returns on {}; one copy of the points "
        "({:.1f} MB, cold) {:.2f} ms ({:.3f} x raw)\n",
        f.points.size(), median(frame), median(raw), median(frame) / median(raw), median(labelled),
        median(labelled) / median(raw), lidar::Scanner::vectorIsa(),
        static_cast<double>(f.points.size() * sizeof(lidar::LidarPoint)) / 1e6, median(copied),
        median(copied) / median(raw));
    return 0;
  }

  // --- The default scene: frames every 300 m of the 6 km route -------------------------------
  const auto p0 = Clock::now();
  const World def = makeWorld(0.0);
  fmt::print(
      "default scenario planned in {:.1f} s; 64 x 2048 frames on {} threads, median of {}; "
      "returns on {}\n\n",
      ms(p0) / 1e3, kThreads, kRepeats, lidar::Scanner::vectorIsa());
  fmt::print(
      "| scene | frames | points | frame ms | raw traversal ms | frame / raw | scene build ms "
      "| peak MB (tiles + BVHs) | x first row ms | x first row MB |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  Stretch instanced, flattened, avx512;
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    instanced = walk(def, *stream, world, arena, scanner, 150.0, 5900.0, 300.0, true);
    printStretch("default, instanced trees, AVX2", instanced, instanced);
  }
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world({false, "avx2"});
    flattened = walk(def, *stream, world, arena, scanner, 150.0, 5900.0, 300.0);
    printStretch("default, flattened trees, AVX2", flattened, instanced);
  }
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world({true, "avx512"});
    avx512 = walk(def, *stream, world, arena, scanner, 150.0, 5900.0, 300.0);
    printStretch("default, instanced trees, AVX-512", avx512, instanced);
  }

  // How rays are handed to Embree, on one typical frame per kilometre.
  fmt::print(
      "\nRaw traversal by how rays reach Embree (same rays, same split, ms; packets of 8 "
      "neighbouring columns of one laser are the scanner's way):\n\n"
      "| at (m) | packets of 8 | one by one | stream (rtcIntersect1M) | packets of 8 lasers of a "
      "column | frame | frame / packets |\n"
      "|---|---|---|---|---|---|---|\n");
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    for (double x = 500.0; x < 6000.0; x += 1000.0) {
      FrameCost c;
      walk(def, *stream, world, arena, scanner, x, x + 1.0, 10.0, true, &c);
      fmt::print("| {:.0f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.3f} |\n", x, c.raw_ms,
                 c.single_ms, c.stream_ms, c.by_column_ms, c.frame_ms, c.frame_ms / c.raw_ms);
    }
  }
  // Beam divergence: sub-rays per pulse against wire returns and time (2.25 mrad, strongest
  // return), on frames where the catenary is within reach.
  fmt::print(
      "\nSub-rays per pulse (beam divergence 2.25 mrad, strongest return; 3 frames along the "
      "default route):\n\n"
      "| sub-rays | rays a frame | frame ms | x 1 sub-ray | wire points a frame | points a frame "
      "|\n"
      "|---|---|---|---|---|---|\n");
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    double base_ms = 0.0;
    for (const int n : {1, 4, 16, 64}) {
      lidar::LidarParams p = scanner.params();
      p.sub_rays = n;
      p.divergence_rad = 0.00225;
      const lidar::Scanner divergent(p);
      double frame_ms = 0.0, wires = 0.0, points = 0.0;
      int frames = 0;
      for (const auto& [pose, scene] : framesAlongTheRoute(def, *stream, world)) {
        const RandomStream random(1, "bench");
        std::vector<double> times;
        lidar::LidarFrame f;
        for (int r = 0; r < (n >= 16 ? 3 : kRepeats); ++r) {
          const auto t0 = Clock::now();
          arena.execute([&] { divergent.scan(scene, pose, random, 0, f); });
          times.push_back(ms(t0));
        }
        frame_ms += median(times);
        for (const auto& pt : f.points)
          wires += pt.cls == scene::cls::kWire;
        points += static_cast<double>(f.points.size());
        ++frames;
      }
      frame_ms /= frames;
      if (n == 1)
        base_ms = frame_ms;
      fmt::print("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.0f} |\n", n, divergent.raysPerFrame(),
                 frame_ms, frame_ms / base_ms, wires / frames, points / frames);
    }
  }
  // --- Where the beams leave the head ---------------------------------------------------------
  // The HDL-64E S3 preset with its calibration's beam offsets (the default run's LiDAR) against
  // the same lasers all cast from the sensor's origin: what the offsets cost a frame, and how
  // far a return moves without them (the same pulse, matched by ring and column: on the ground a
  // beam's 0.14-0.22 m of height moves its hit along the ground by that over the tangent of its
  // depression, metres for the rings near the horizon).
  fmt::print(
      "\nBeam origins (HDL-64E S3 preset, 2083 columns, no noise; 3 frames along the default "
      "route):\n\n"
      "| beams from | frame ms | x from the origin | points a frame | return moved, median mm | "
      "moved, 95th percentile mm |\n"
      "|---|---|---|---|---|---|\n");
  {
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    lidar::LidarParams p = scanner.params();
    p.pattern = lidar::preset("hdl64", 10.0);
    p.range_sigma_m = 0.0;
    lidar::LidarParams centred = p;
    for (lidar::Laser& l : centred.pattern.lasers)
      l.vertical_offset_m = l.horizontal_offset_m = 0.0;
    const lidar::Scanner offset(p), origin(centred);
    double ms_offset = 0.0, ms_origin = 0.0, points = 0.0;
    std::vector<double> moved;
    for (const auto& [pose, scene] : framesAlongTheRoute(def, *stream, world)) {
      const RandomStream random(1, "bench");
      lidar::LidarFrame a, b;
      std::vector<double> ta, tb;
      for (int r = 0; r < kRepeats; ++r) {  // alternating, as drifts in speed hit both
        auto t0 = Clock::now();
        arena.execute([&] { offset.scan(scene, pose, random, 0, a); });
        ta.push_back(ms(t0));
        t0 = Clock::now();
        arena.execute([&] { origin.scan(scene, pose, random, 0, b); });
        tb.push_back(ms(t0));
      }
      ms_offset += median(ta);
      ms_origin += median(tb);
      points += static_cast<double>(a.points.size());
      std::map<std::uint32_t, Eigen::Vector3f> at;
      for (const auto& pt : b.points)
        at[static_cast<std::uint32_t>(pt.ring) << 16 | pt.column] = pt.xyz;
      for (const auto& pt : a.points) {
        const auto it = at.find(static_cast<std::uint32_t>(pt.ring) << 16 | pt.column);
        if (it == at.end())
          continue;
        moved.push_back((pt.xyz - it->second).norm());
      }
    }
    fmt::print("| the calibration's offsets | {:.2f} | {:.3f} | {:.0f} | {:.1f} | {:.1f} |\n",
               ms_offset / 3, ms_offset / ms_origin, points / 3, 1e3 * median(moved),
               1e3 * percentile(moved, 0.95));
    fmt::print("| the sensor's origin | {:.2f} | 1 | | | |\n", ms_origin / 3);
  }
  fogTable(def, arena, scanner);
  // --- Terrain as triangles or as Embree grids ------------------------------------------------
  // The full 1 m height grid handed to Embree as triangles or as grid geometry (the same surface:
  // unit_lidar's HeightFields test), against the CGAL-simplified mesh the scene uses.
  fmt::print(
      "\nTerrain as triangles or as Embree grids (frames every 600 m):\n\n"
      "| terrain | frames | points | frame ms | raw traversal ms | scene build ms | peak MB (tiles "
      "+ BVHs) | x simplified ms | x simplified MB |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  {
    const auto row = [](const char* name, const Stretch& s, const Stretch& base) {
      fmt::print("| {} | {} | {:.0f} | {:.2f} | {:.2f} | {:.1f} | {:.1f} | {:.2f} | {:.2f} |\n",
                 name, s.frames, s.points, s.frame_ms, s.raw_ms, s.build_ms, s.peak_mb,
                 s.frame_ms / base.frame_ms, s.peak_mb / base.peak_mb);
    };
    auto stream = def.stage->environment->stream(16);
    lidar::RayWorld world;
    const Stretch simplified = walk(def, *stream, world, arena, scanner, 150.0, 5900.0, 600.0);
    row("simplified (CGAL, 2 cm), triangles", simplified, simplified);
    const World full = makeWorld(0.0, 0.0);
    for (const bool grids : {false, true}) {
      auto full_stream = full.stage->environment->stream(16);
      lidar::RayWorld full_world({true, "avx2", grids});
      const Stretch s = walk(full, *full_stream, full_world, arena, scanner, 150.0, 5900.0, 600.0);
      row(grids ? "full 1 m grid, Embree grids" : "full 1 m grid, triangles", s, simplified);
    }
  }
  if (quick)
    return 0;

  routeLength(arena, scanner);
  return 0;
}
