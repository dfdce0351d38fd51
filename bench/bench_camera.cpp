// The camera's costs on the default scene: ms per frame for the colour pass with depth plus the
// id pass (semantic and instance) at 1242 × 375 and 1920 × 1080, triangles drawn, with and
// without frustum culling and level of detail, the image difference those cause against the full
// scene, frame time 1 km and 100 km along a route, and the PNG encoding of each image against
// libpng's default settings. Software OpenGL (Mesa llvmpipe) under a private Xvfb when DISPLAY
// is unset.
//
//   bench_camera [--quick | --tunnel]   (--quick: the default scene only; --tunnel: its frames
//   at the first tunnel's portal only)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include <Eigen/Geometry>

#include "bench_world.hpp"
#include "trainsim/camera/renderer.hpp"
#include "trainsim/camera/x_display.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/terrain/daylight.hpp"

namespace {

using namespace trainsim;
using bench::Clock;
using bench::median;
using bench::ms;

constexpr int kRepeats = 5;
constexpr double kDrawDistance = 400.0;  // the default camera's

using bench::makeWorld;
using bench::World;

// The default scenario's front camera on the body at time t.
Eigen::Isometry3d cameraPose(const sim::Trajectory& trajectory, TimeNs t) {
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.linear() = rotationBodyFromKittiCamera();
  T_body_cam.translation() = Eigen::Vector3d(10.5, 0.0, 3.2);
  return trajectory.at(t).pose() * T_body_cam;
}

// What the renderer leaves out: nothing (everything in the window at full detail), what lies
// outside the view frustum, or that and detail below a pixel (the run's setting).
enum class Detail { kFull, kCulled, kLod, kLodFxaa };

camera::RendererOptions options(int width, int height, Detail detail) {
  camera::RendererOptions o;
  o.intrinsics = camera::Intrinsics::fromHorizontalFov(width, height, 81.6 * M_PI / 180.0);
  o.far_m = kDrawDistance;
  o.cull = detail != Detail::kFull;
  o.lod_pixels = detail == Detail::kLod || detail == Detail::kLodFxaa ? 1.0 : 0.0;
  o.fxaa = detail == Detail::kLodFxaa;
  return o;
}

// How much an image differs from a reference of the same view.
struct Difference {
  double rgb_mean = 0.0;       // mean absolute difference per channel, 0..255
  double rgb_changed = 0.0;    // share of pixels with any channel off by more than 8
  double class_changed = 0.0;  // share of pixels with another class
  double depth_changed = 0.0;  // share of pixels whose depth moved by more than 5 cm
};

Difference difference(const camera::CameraImages& a, const camera::CameraImages& ref) {
  Difference d;
  const std::size_t pixels = ref.semantic.size();
  for (std::size_t i = 0; i < pixels; ++i) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int e = std::abs(int(a.rgb[3 * i + c]) - int(ref.rgb[3 * i + c]));
      d.rgb_mean += e;
      worst = std::max(worst, e);
    }
    d.rgb_changed += worst > 8;
    d.class_changed += a.semantic[i] != ref.semantic[i];
    d.depth_changed += std::abs(a.depth[i] - ref.depth[i]) > 0.05f;
  }
  d.rgb_mean /= 3.0 * double(pixels);
  d.rgb_changed /= double(pixels);
  d.class_changed /= double(pixels);
  d.depth_changed /= double(pixels);
  return d;
}

// Frames along a stretch of the main track: every `step_m` from `from_m` to `to_m`.
struct Stretch {
  double frame_ms = 0.0, first_ms = 0.0, window_ms = 0.0;  // means
  double triangles = 0.0, objects = 0.0;
  Difference diff;  // against the reference images, when given (the worst frame's)
  int frames = 0;
};

// The images a frame is compared with.
using Reference =
    std::function<camera::CameraImages(const scene::SceneWindow&, const Eigen::Isometry3d&)>;

// The images of `renderer` under the run's default light (`shade`: as render()'s).
Reference imagesOf(const camera::Renderer& renderer, const camera::Lighting* shade = nullptr) {
  return [&renderer, shade](const scene::SceneWindow& window, const Eigen::Isometry3d& T) {
    return renderer.render(window, T, camera::Lighting(), shade);
  };
}

Stretch walk(const World& w, scene::SceneStream& stream, const camera::Renderer& renderer,
             double from_m, double to_m, double step_m, const Reference& reference = {},
             const camera::Lighting* shade = nullptr) {
  const sim::Trajectory& trajectory = w.plan->trajectory();
  const camera::Lighting light;
  Stretch s;
  TimeNs t = 0;
  for (double x = from_m; x < to_m; x += step_m) {
    while (t < trajectory.endTime() && trajectory.at(t).chainage_m < x)
      t += 10 * trajectory.samplePeriod();
    const Eigen::Isometry3d T = cameraPose(trajectory, t);
    const auto w0 = Clock::now();
    const scene::SceneWindow window = stream.window(T.translation(), kDrawDistance);
    s.window_ms += ms(w0);
    std::vector<double> times;
    camera::CameraImages img;
    for (int r = 0; r < kRepeats; ++r) {
      const auto t0 = Clock::now();
      img = renderer.render(window, T, light, shade);
      times.push_back(ms(t0));
    }
    s.first_ms += times.front();
    s.frame_ms += median(times);
    s.triangles += double(img.triangles);
    s.objects += double(img.objects);
    if (reference) {
      const Difference d = difference(img, reference(window, T));
      s.diff.rgb_mean = std::max(s.diff.rgb_mean, d.rgb_mean);
      s.diff.rgb_changed = std::max(s.diff.rgb_changed, d.rgb_changed);
      s.diff.class_changed = std::max(s.diff.class_changed, d.class_changed);
      s.diff.depth_changed = std::max(s.diff.depth_changed, d.depth_changed);
    }
    ++s.frames;
  }
  for (double* v : {&s.frame_ms, &s.first_ms, &s.window_ms, &s.triangles, &s.objects})
    *v /= s.frames;
  return s;
}

void printRow(const std::string& name, const Stretch& s, const Stretch& base, bool diff) {
  fmt::print("| {} | {} | {:.0f} | {:.0f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} |", name, s.frames,
             s.objects, s.triangles, s.frame_ms, s.first_ms, s.window_ms,
             s.frame_ms / base.frame_ms);
  if (diff)
    fmt::print(" {:.3f} | {:.4f} | {:.4f} | {:.4f} |", s.diff.rgb_mean, 100 * s.diff.rgb_changed,
               100 * s.diff.class_changed, 100 * s.diff.depth_changed);
  else
    fmt::print(" – | – | – | – |");
  fmt::print("\n");
}

// Encoding the images of frames every 300 m of the default route as the run does (its preset
// per image) against libpng's default (all five filters tried per row, zlib level 6): time
// (medians of 3) and size, summed over the frames. Lossless both ways.
void pngTable(const World& w) {
  const camera::Renderer renderer(options(1242, 375, Detail::kLod));
  auto stream = w.stage->environment->stream(16);
  const sim::Trajectory& trajectory = w.plan->trajectory();
  struct Sum {
    double ms = 0.0, base_ms = 0.0, bytes = 0.0, base_bytes = 0.0;
  };
  Sum rgb, depth, semantic, object;
  const auto add = [](Sum& sum, const auto& encode, io::PngContent content) {
    std::vector<double> t, b;
    std::string out, base;
    for (int r = 0; r < 3; ++r) {
      auto t0 = Clock::now();
      out = encode(content);
      t.push_back(ms(t0));
      t0 = Clock::now();
      base = encode(io::PngContent::kLibpngDefault);
      b.push_back(ms(t0));
    }
    sum.ms += median(t);
    sum.base_ms += median(b);
    sum.bytes += double(out.size());
    sum.base_bytes += double(base.size());
  };
  int frames = 0;
  TimeNs t = 0;
  for (double x = 150.0; x < 5900.0; x += 300.0, ++frames) {
    while (t < trajectory.endTime() && trajectory.at(t).chainage_m < x)
      t += 10 * trajectory.samplePeriod();
    const Eigen::Isometry3d T = cameraPose(trajectory, t);
    const camera::CameraImages img =
        renderer.render(stream->window(T.translation(), kDrawDistance), T, camera::Lighting());
    // Depth in 1/256 m as KITTI's depth maps (0: nothing within 255 m), as the run writes it.
    std::vector<std::uint16_t> mm(img.depth.size());
    for (std::size_t i = 0; i < mm.size(); ++i)
      mm[i] = img.depth[i] > 0.0f && img.depth[i] < 255.0f
                  ? static_cast<std::uint16_t>(std::lround(img.depth[i] * 256.0))
                  : 0;
    const int W = img.width, H = img.height;
    add(
        rgb, [&](io::PngContent c) { return io::encodePngRgb8(W, H, img.rgb, c); },
        io::PngContent::kImage);
    add(
        depth, [&](io::PngContent c) { return io::encodePngGray16(W, H, mm, c); },
        io::PngContent::kMeasurement);
    add(
        semantic, [&](io::PngContent c) { return io::encodePngGray8(W, H, img.semantic, c); },
        io::PngContent::kLabels);
    add(
        object, [&](io::PngContent c) { return io::encodePngGray16(W, H, img.object, c); },
        io::PngContent::kLabels);
  }
  fmt::print(
      "\nPNG encoding, 1242 x 375, {} frames: the run's preset against libpng's default\n\n"
      "| image | preset | ms an image | default ms | time / default | size / default |\n"
      "|---|---|---|---|---|---|\n",
      frames);
  Sum all;
  for (const auto& [name, preset, s] :
       {std::tuple{"colour (RGB 8)", "Up, level 4", rgb},
        std::tuple{"depth (grey 16)", "Sub, level 4", depth},
        std::tuple{"semantic (grey 8)", "Up, level 4, run-length", semantic},
        std::tuple{"instance (grey 16)", "Up, level 4", object}}) {
    fmt::print("| {} | {} | {:.1f} | {:.1f} | {:.2f} | {:.3f} |\n", name, preset, s.ms / frames,
               s.base_ms / frames, s.ms / s.base_ms, s.bytes / s.base_bytes);
    all.ms += s.ms;
    all.base_ms += s.base_ms;
    all.bytes += s.bytes;
    all.base_bytes += s.base_bytes;
  }
  fmt::print("| all four | | {:.1f} | {:.1f} | {:.2f} | {:.3f} |\n", all.ms / frames,
             all.base_ms / frames, all.ms / all.base_ms, all.bytes / all.base_bytes);
}

void tunnelRows(const World& def, double from, double to,
                const std::shared_ptr<const terrain::TunnelDaylight>& daylight, Detail detail);

// Frames before and into the default route's first tunnel, each surface lit by the daylight
// that reaches it (the run's way: the id pass first, then one colour pass lighting each pixel's
// surface by its share) against the day's light everywhere, and the images against a
// reference made independently of the run's shader: a render under each lighting alone,
// blended per pixel by the share of the surface the pixel shows.
void tunnelTable(const World& def) {
  const track::Route& route = def.stage->railway->route();
  const auto tunnel = std::find_if(route.blocks.begin(), route.blocks.end(), [](const auto& b) {
    return b.type == track::BlockType::kTunnel;
  });
  if (tunnel == route.blocks.end())
    return;
  const auto daylight = std::make_shared<const terrain::TunnelDaylight>(
      route, def.stage->railway->layout(), def.stage->environment->params().terrain);
  const double from = std::max(20.0, tunnel->chainage_begin_m - 150.0);
  const double to = tunnel->chainage_begin_m + 100.0;
  fmt::print(
      "\nTunnel portal (main chainage {:.0f}-{:.0f} m, the first tunnel's portal at {:.0f} m, "
      "every 25 m; 1242 x 375, culled, levels of detail; the differences against the blend of "
      "a render under each lighting alone, by each pixel's share):\n\n| lighting | frames | ms "
      "a frame | x daylight everywhere | RGB mean diff | RGB pixels changed % |\n"
      "|---|---|---|---|---|---|\n",
      from, to, tunnel->chainage_begin_m);
  for (const Detail detail : {Detail::kLodFxaa, Detail::kLod})
    tunnelRows(def, from, to, daylight, detail);
}

// tunnelTable()'s two rows at one level of detail, frames every 25 m from `from` to `to`.
void tunnelRows(const World& def, double from, double to,
                const std::shared_ptr<const terrain::TunnelDaylight>& daylight, Detail detail) {
  camera::RendererOptions o = options(1242, 375, detail);
  const camera::Renderer day(o);
  o.daylight = [daylight](std::span<const Eigen::Vector3d> points, std::span<float> shares) {
    daylight->shares(points, shares);
  };
  o.shade_meets = [daylight](const scene::Box3d& box) { return daylight->meets(box); };
  const camera::Renderer shaded(o);  // the run's
  // The run's tunnel lighting: the night's faint sky and the train's two headlights (1 m above
  // the body's reference, 0.6 m either side, 0.5 m ahead of the camera, dipped 1°; in the
  // camera's axes: x right, y down, z forward).
  camera::Lighting shade;
  shade.sun_intensity = 0.0;
  shade.ambient = 0.06;
  for (const double x : {-0.6, 0.6}) {
    camera::Spot lamp;
    lamp.position = Eigen::Vector3d(x, 2.2, 0.5);
    lamp.direction = Eigen::Vector3d(0.0, 0.0175, 1.0).normalized();
    lamp.half_angle_deg = 15.0;
    lamp.half_distance_m = 35.0;
    shade.spots.push_back(lamp);
  }
  const Reference blend = [&](const scene::SceneWindow& window, const Eigen::Isometry3d& T) {
    camera::CameraImages a = day.render(window, T, camera::Lighting());
    const camera::CameraImages b = day.render(window, T, shade);
    const camera::Intrinsics& k = o.intrinsics;
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
        const double z = a.depth[i];
        if (z <= 0.0)
          continue;
        const double s =
            (*daylight)(T * Eigen::Vector3d((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z));
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c)
          a.rgb[c] = static_cast<std::uint8_t>(std::lround(b.rgb[c] + s * (a.rgb[c] - b.rgb[c])));
      }
    return a;
  };
  auto stream = def.stage->environment->stream(16);
  const Stretch a = walk(def, *stream, day, from, to, 25.0);
  const Stretch c = walk(def, *stream, shaded, from, to, 25.0, blend, &shade);
  const char* name = detail == Detail::kLodFxaa ? ", FXAA (the run's)" : ", no FXAA";
  fmt::print("| daylight everywhere{} | {} | {:.1f} | 1.000 | – | – |\n", name, a.frames,
             a.frame_ms);
  fmt::print("| by surface, in one colour pass{} | {} | {:.1f} | {:.3f} | {:.3f} | {:.3f} |\n",
             name, c.frames, c.frame_ms, c.frame_ms / a.frame_ms, c.diff.rgb_mean,
             100.0 * c.diff.rgb_changed);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const auto display = camera::XDisplay::ensure();
  if (argc > 1 && std::strcmp(argv[1], "--profile") == 0) {
    // One frame of the default scene rendered over and over, for a profiler.
    const World w = makeWorld(0.0);
    auto stream = w.stage->environment->stream(16);
    const camera::Renderer renderer(options(1242, 375, Detail::kLod));
    const Eigen::Isometry3d T = cameraPose(w.plan->trajectory(), 60'000'000'000);
    const scene::SceneWindow window = stream->window(T.translation(), kDrawDistance);
    renderer.render(window, T, camera::Lighting());
    const auto t0 = Clock::now();
    camera::CameraImages img;
    for (int i = 0; i < 50; ++i)
      img = renderer.render(window, T, camera::Lighting());
    fmt::print("{:.1f} ms a frame, {} objects, {} triangles\n", ms(t0) / 50, img.objects,
               img.triangles);
    return 0;
  }
  const auto p0 = Clock::now();
  const World def = makeWorld(0.0);
  if (argc > 1 && std::strcmp(argv[1], "--tunnel") == 0) {
    tunnelTable(def);
    return 0;
  }
  fmt::print(
      "default scenario planned in {:.1f} s; colour + depth + id passes, draw distance {:.0f} m, "
      "median of {} renders a frame (first: with the actors made)\n\n",
      ms(p0) / 1e3, kDrawDistance, kRepeats);
  fmt::print(
      "| frame | frames | objects | triangles | ms a frame | first render ms | window ms | x "
      "first row | RGB mean diff | RGB pixels changed % | class pixels changed % | depth pixels "
      "changed > 5 cm % |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [width, height] : {std::pair{1242, 375}, std::pair{1920, 1080}}) {
    const camera::Renderer full(options(width, height, Detail::kFull));
    const camera::Renderer culled(options(width, height, Detail::kCulled));
    const camera::Renderer lod(options(width, height, Detail::kLod));
    auto stream = def.stage->environment->stream(16);
    const Stretch base = walk(def, *stream, full, 150.0, 5900.0, 300.0);
    printRow(fmt::format("{} x {}, everything in the window", width, height), base, base, false);
    const Stretch c = walk(def, *stream, culled, 150.0, 5900.0, 300.0, imagesOf(full));
    printRow(fmt::format("{} x {}, frustum culled", width, height), c, base, true);
    const Stretch l = walk(def, *stream, lod, 150.0, 5900.0, 300.0, imagesOf(full));
    printRow(fmt::format("{} x {}, culled + levels of detail (1 px)", width, height), l, base,
             true);
    // FXAA smooths the colour image alone: its class and depth columns must stay those of the
    // row above.
    const camera::Renderer fxaa(options(width, height, Detail::kLodFxaa));
    const Stretch f = walk(def, *stream, fxaa, 150.0, 5900.0, 300.0, imagesOf(full));
    printRow(
        fmt::format("{} x {}, culled + levels of detail + FXAA (the run's default)", width, height),
        f, base, true);
  }
  tunnelTable(def);
  pngTable(def);
  if (quick)
    return 0;

  // --- 1 km and 100 km along one 100 km route --------------------------------------------------
  const auto p1 = Clock::now();
  const World far = makeWorld(100'000.0);
  fmt::print("\n100 km route planned in {:.1f} s; 1242 x 375, culled, levels of detail\n\n",
             ms(p1) / 1e3);
  fmt::print(
      "| stretch | frames | objects | triangles | ms a frame | first render ms | window ms | x km "
      "1.5-2.5 |\n|---|---|---|---|---|---|---|---|\n");
  const camera::Renderer renderer(options(1242, 375, Detail::kLod));
  auto stream = far.stage->environment->stream(16);
  const Stretch near = walk(far, *stream, renderer, 1500.0, 2500.0, 50.0);
  const Stretch end = walk(far, *stream, renderer, 98'500.0, 99'500.0, 50.0);
  for (const auto& [name, s] : {std::pair{"km 1.5-2.5", near}, std::pair{"km 98.5-99.5", end}})
    fmt::print("| {} | {} | {:.0f} | {:.0f} | {:.1f} | {:.1f} | {:.1f} | {:.3f} |\n", name,
               s.frames, s.objects, s.triangles, s.frame_ms, s.first_ms, s.window_ms,
               s.frame_ms / near.frame_ms);
  return 0;
}
