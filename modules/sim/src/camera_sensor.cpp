#include "camera_sensor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "class_counts.hpp"
#include "trainsim/camera/exposure.hpp"
#include "trainsim/camera/lens.hpp"
#include "trainsim/camera/renderer.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/scene/mesh.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/instance_table.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"
#include "trainsim/terrain/daylight.hpp"

namespace trainsim::sim {
namespace {

static_assert(std::endian::native == std::endian::little,
              "PFM depth is written little-endian by copying memory as is");

namespace units = scenario::units;
constexpr scenario::Unit kM = units::si("m");

// Sun positions (azimuth from north, clockwise; elevation) of the daytime presets
// (sensors-reference.md 7.5), or the explicit angles.
enum class Daytime { kNoon, kMorning, kEvening, kNight, kCustom };
constexpr EnumName<Daytime> kDaytimeNames[] = {{Daytime::kNoon, "noon"},
                                               {Daytime::kMorning, "morning"},
                                               {Daytime::kEvening, "evening"},
                                               {Daytime::kNight, "night"},
                                               {Daytime::kCustom, "custom"}};
constexpr std::span<const EnumName<Daytime>> enumNames(Daytime) {
  return kDaytimeNames;
}

// sensors.cameras[]
struct CameraConfig {
  SensorBasics basics{"camera", 100'000'000, {Eigen::Vector3d(10.5, 0.0, 3.2)}};
  int width = 1242, height = 375;
  double hfov_rad = 81.6 * kRadPerDeg;  // KITTI's colour cameras: fx 718.9 px over 1242 px
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  camera::Distortion distortion;
  double near_m = 0.5;
  double far_m = 400.0;
  double depth_max_m = 100.0;
  bool rgb = true, depth = true, semantic = true, instance = true, semantic_preview = false;
  bool depth_float = false;
  Daytime daytime = Daytime::kNoon;
  double sun_azimuth_rad = 180.0 * kRadPerDeg, sun_elevation_rad = 55.0 * kRadPerDeg;
  double fog_visibility_m = 0.0;
  bool headlights = false;
  double shutter_s = 0.01, f_number = 16.0, iso = 100.0;
  double read_noise_dn = 0.0, shot_noise_dn = 0.0;
  bool fxaa = true;
};

const scenario::Binding<camera::Distortion>& distortionBinding() {
  static const scenario::Binding<camera::Distortion> binding = [] {
    using D = camera::Distortion;
    scenario::Binding<D> b;
    b.number("k1", &D::k1, units::kNone,
             "Radial: a pinhole point (x, y) = (X/Z, Y/Z) at r is imaged at (x, y) (1 + k1 r^2 "
             "+ k2 r^4 + k3 r^6) plus the tangential terms")
        .range(-10, 10);
    b.number("k2", &D::k2, units::kNone, "Radial, r^4").range(-10, 10);
    b.number("p1", &D::p1, units::kNone, "Tangential: + 2 p1 x y in x, p1 (r^2 + 2 y^2) in y")
        .range(-1, 1);
    b.number("p2", &D::p2, units::kNone, "Tangential: p2 (r^2 + 2 x^2) in x, + 2 p2 x y in y")
        .range(-1, 1);
    b.number("k3", &D::k3, units::kNone, "Radial, r^6").range(-10, 10);
    return b;
  }();
  return binding;
}

camera::Intrinsics intrinsics(const CameraConfig& c);

const scenario::Binding<CameraConfig>& cameraBinding() {
  static const scenario::Binding<CameraConfig> binding = [] {
    using C = CameraConfig;
    scenario::Binding<C> b;
    b.embed(&C::basics,
            sensorBasics({"<name>.csv (one row per frame) and the image, depth, semantic and "
                          "instance folders of its position in the list (image_2, depth_2, …; "
                          "image_3, … for the second)",
                          10'000'000, 10'000'000'000,
                          "Frame period; it must equal dataset.frame_period_ns (KITTI pairs "
                          "every image with a line of times.txt and poses.txt)",
                          "Pose of the camera (x forward, y left, z up before KITTI's camera "
                          "axes x right, y down, z forward are applied); the default is the "
                          "windscreen"}));
    b.integer("width", &C::width, "px", "Image width").range(16, 8192);
    b.integer("height", &C::height, "px", "Image height").range(16, 8192);
    b.number("horizontal_fov_deg", &C::hfov_rad, units::kDegree,
             "Horizontal field of view, when fx is 0 (square pixels, principal point at the "
             "centre)")
        .range(1, 170);
    b.number("fx", &C::fx, units::kNone, "Focal length in pixels; 0: from horizontal_fov_deg")
        .range(0, 1e6);
    b.number("fy", &C::fy, units::kNone, "Vertical focal length in pixels; 0: fx").range(0, 1e6);
    b.number("cx", &C::cx, units::kNone,
             "Principal point column, pixels from the centre of the top-left pixel; 0: the "
             "image's centre column")
        .range(0, 1e6);
    b.number("cy", &C::cy, units::kNone, "Principal point row (see cx); 0: the image's centre row")
        .range(0, 1e6);
    b.object("distortion", &C::distortion, distortionBinding(),
             "Lens distortion (Brown-Conrady, OpenCV's coefficients; all 0: a pinhole). The "
             "camera renders a pinhole image large enough to cover every ray, then remaps it "
             "with OpenCV (bilinear for RGB, nearest for depth and ids); calib.txt's P stays "
             "the pinhole K and D<N> lists k1 k2 p1 p2 k3");
    b.number("near_m", &C::near_m, kM,
             "Nothing nearer is drawn; the depth step at z is about z^2 / (near * 2^24): 1.2 mm "
             "at 100 m for 0.5 m")
        .range(0.05, 10);
    b.number("draw_distance_m", &C::far_m, kM,
             "Nothing farther is drawn (the far plane); at least depth_max_m when depth is on")
        .range(10, 5000);
    b.number("depth_max_m", &C::depth_max_m, kM,
             "Depth images hold 0 beyond this (KITTI's 16-bit depth ends at 255.99 m)")
        .range(1, 255);
    b.boolean("rgb", &C::rgb, "Write image_N/*.png (8-bit RGB)");
    b.boolean("depth", &C::depth,
              "Write depth_N/*.png: uint16 metres * 256 along the optical axis, 0 for nothing "
              "within depth_max_m (KITTI's depth convention)");
    b.boolean("depth_float", &C::depth_float,
              "Also write depth_N/*.pfm: float32 metres along the optical axis, 0 for nothing "
              "drawn (not clipped at depth_max_m; Portable Float Map, which OpenCV's imread "
              "reads)");
    b.boolean("semantic", &C::semantic, "Write semantic_N/*.png: uint8 class id per pixel");
    b.boolean("semantic_preview", &C::semantic_preview,
              "Also write semantic_rgb_N/*.png: the semantic image in the classes' colours "
              "(the dataset's classes.yaml color_map, from resources/classes.json), to look "
              "at");
    b.boolean("instance", &C::instance,
              "Write instance_N/*.png: uint16 instance id per pixel, the id the LiDAR labels use "
              "(instances.csv), 0 for stuff");
    b.choice("daytime", &C::daytime,
             "Sun position: noon (south, 55 deg up), morning (east, 15 deg), evening (west, 10 "
             "deg), night (no sun, a faint sky, the train's headlights on) or custom "
             "(sun_azimuth_deg, sun_elevation_deg); a sun under 20 deg reddens the sky's "
             "horizon and darkens its zenith. Daylight reaches a tunnel's bore only near its "
             "portals: each surface's share of it falls from 1 at a portal to 0 at 50 m in, "
             "the headlights light the rest, so a tunnel seen from outside is dark inside and "
             "the world seen from inside daylit");
    b.number("sun_azimuth_deg", &C::sun_azimuth_rad, units::kDegree,
             "Custom sun azimuth, clockwise from north (world y)")
        .range(0, 360);
    b.number("sun_elevation_deg", &C::sun_elevation_rad, units::kDegree,
             "Custom sun elevation above the horizon")
        .range(0, 90);
    b.number("fog_visibility_m", &C::fog_visibility_m, kM,
             "Meteorological visibility of fog (2 % contrast, Koschmieder: extinction 3.912 / "
             "visibility, applied by each pixel's range; the fog lit as the scene is, dark at "
             "night); 0: clear")
        .range(0, 100000);
    b.boolean("headlights", &C::headlights,
              "The train's two headlights (1 m above the body's reference, 0.6 m either side of "
              "the centre, 0.5 m ahead of the camera; 15 deg cones dipped 1 deg, half the light "
              "at 35 m) light the scene, at any daytime (always on at night)");
    b.number("shutter_s", &C::shutter_s, units::si("s"),
             "Exposure time. The presets' colours are those of a sunny-16 exposure (1/100 s at "
             "f/16, ISO 100); other settings scale their light (linear, not the sRGB values) "
             "by shutter_s * iso / f_number^2 relative to it, clipping at white")
        .range(1e-6, 10);
    b.number("f_number", &C::f_number, units::kNone, "Aperture, the f-number N").range(0.5, 64);
    b.number("iso", &C::iso, units::kNone, "Sensitivity, ISO").range(10, 409600);
    b.boolean("fxaa", &C::fxaa,
              "Smooth the RGB image's edges (FXAA, VTK's post-process: stair-steps on rails and "
              "masts, moire on distant sleepers and wires broken into dashes soften); depth, "
              "semantic and instance images stay per pixel. Off: the raw rasterised picture");
    b.number("read_noise_dn", &C::read_noise_dn, units::kNone,
             "Sensor noise: Gaussian read noise, standard deviation in steps of 1/255 of linear "
             "light, before the sRGB encoding (in the PNG's 8-bit steps that is up to 13 times "
             "as much near black, less in the highlights); 0: none")
        .range(0, 64);
    b.number("shot_noise_dn", &C::shot_noise_dn, units::kNone,
             "Sensor noise: photon shot noise, standard deviation in steps of 1/255 of linear "
             "light at white, before the sRGB encoding (it grows as the square root of the "
             "signal); 0: none")
        .range(0, 64);
    b.check([](const C& c, const scenario::FieldPaths<C>& at, std::vector<scenario::Problem>& out) {
      if (c.near_m >= c.far_m)
        out.push_back({at(c.near_m), "must be below " + at.key(c.far_m)});
      if (c.depth && c.depth_max_m > c.far_m)
        out.push_back({at(c.depth_max_m), "must not exceed " + at.key(c.far_m)});
      if (!c.rgb && !c.depth && !c.depth_float && !c.semantic && !c.semantic_preview && !c.instance)
        out.push_back({at(c.rgb), "a camera must write at least one image"});
      if (c.fx == 0.0 && c.fy > 0.0)
        out.push_back({at(c.fy), "needs " + at.key(c.fx) + ": with fx 0, " + at.key(c.hfov_rad) +
                                     " sets both (square pixels)"});
      if (c.width <= 0 || c.height <= 0)
        return;
      // The principal point within the image, as the lower bound of cx and cy has it.
      const bool centre_inside = c.cx <= c.width - 1.0 && c.cy <= c.height - 1.0;
      if (c.cx > c.width - 1.0)
        out.push_back({at(c.cx), fmt::format("must lie within the image: at most {} (width - 1)",
                                             c.width - 1)});
      if (c.cy > c.height - 1.0)
        out.push_back({at(c.cy), fmt::format("must lie within the image: at most {} (height - 1)",
                                             c.height - 1)});
      // The field of view the intrinsics give over the pixels' outer edges, held to what
      // horizontal_fov_deg allows: fx, fy or a tall image can reach past it, where the
      // renderer's frustum degenerates and the near plane cuts the ground away.
      const camera::Intrinsics k = intrinsics(c);
      const auto fov_deg = [](double centre, int size, double f) {
        return (std::atan((centre + 0.5) / f) + std::atan((size - 0.5 - centre) / f)) / kRadPerDeg;
      };
      constexpr double kMaxFovDeg = 170.0;
      if (const double h = fov_deg(k.cx, c.width, k.fx); centre_inside && h > kMaxFovDeg)
        out.push_back({at(c.fx > 0.0 ? c.fx : c.hfov_rad),
                       fmt::format("gives a horizontal field of view of {:.1f} deg ({} px at fx "
                                   "{:.4g} px), more than {} deg",
                                   h, c.width, k.fx, kMaxFovDeg)});
      if (const double v = fov_deg(k.cy, c.height, k.fy); centre_inside && v > kMaxFovDeg)
        out.push_back({c.fy > 0.0   ? at(c.fy)
                       : c.fx > 0.0 ? at(c.fx)
                                    : at(c.height),
                       fmt::format("gives a vertical field of view of {:.1f} deg ({} px at fy "
                                   "{:.4g} px), more than {} deg",
                                   v, c.height, k.fy, kMaxFovDeg)});
      // A lens the renderer cannot invert over the image: validate refuses what generate would.
      if (!c.distortion.none() && centre_inside)
        if (const std::string why = camera::lensProblem(k, c.distortion); !why.empty())
          out.push_back({at(c.distortion), why});
    });
    return b;
  }();
  return binding;
}

// The camera's pose on the body: the mount, then KITTI's camera axes.
Eigen::Isometry3d bodyFromCamera(const Mount& mount) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = mount.r_body_sensor * rotationBodyFromKittiCamera();
  T.translation() = mount.position_m;
  return T;
}

camera::Intrinsics intrinsics(const CameraConfig& c) {
  camera::Intrinsics k = camera::Intrinsics::fromHorizontalFov(c.width, c.height, c.hfov_rad);
  if (c.fx > 0.0) {
    k.fx = c.fx;
    k.fy = c.fy > 0.0 ? c.fy : c.fx;
  }
  if (c.cx > 0.0)
    k.cx = c.cx;
  if (c.cy > 0.0)
    k.cy = c.cy;
  return k;
}

// The light a surface facing the sky gets: the sky's (ambient) and the sun's diffuse share.
double skywardLight(const camera::Lighting& l) {
  return l.ambient + (1.0 - l.ambient) * l.sun_intensity;
}

camera::Lighting lighting(const CameraConfig& c) {
  double az = c.sun_azimuth_rad, el = c.sun_elevation_rad;
  switch (c.daytime) {
    case Daytime::kNoon:
      az = 180.0 * kRadPerDeg, el = 55.0 * kRadPerDeg;
      break;
    case Daytime::kMorning:
      az = 90.0 * kRadPerDeg, el = 15.0 * kRadPerDeg;
      break;
    case Daytime::kEvening:
      az = 270.0 * kRadPerDeg, el = 10.0 * kRadPerDeg;
      break;
    case Daytime::kNight:
    case Daytime::kCustom:
      break;
  }
  camera::Lighting l;
  // World axes: x east, y north, z up.
  l.sun_direction =
      Eigen::Vector3d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
  // A low sun lights less, and the sky's light is a larger share.
  l.sun_intensity = 0.55 + 0.45 * std::sin(el);
  // A low sun reddens the horizon and darkens the zenith (a look, not a sky model: under 20 deg
  // of elevation the colours move linearly towards a sunrise sky's, all the way at 0 deg); a sun
  // higher than that leaves the renderer's clear day sky as it is.
  const double low = std::clamp((20.0 * kRadPerDeg - el) / (20.0 * kRadPerDeg), 0.0, 1.0);
  const auto towards = [&](scene::Rgb from, scene::Rgb to) {
    scene::Rgb out{};
    for (std::size_t i = 0; i < 3; ++i)
      out[i] = static_cast<std::uint8_t>(std::lround(from[i] + low * (to[i] - from[i])));
    return out;
  };
  l.sky_horizon = towards(l.sky_horizon, {240, 176, 128});
  l.sky_zenith = towards(l.sky_zenith, {72, 100, 160});
  if (c.daytime == Daytime::kNight) {
    l.sun_intensity = 0.0;
    l.ambient = 0.06;
    l.sky_zenith = {6, 9, 22};
    l.sky_horizon = {18, 22, 38};
  }
  if (c.headlights || c.daytime == Daytime::kNight) {
    // Two lamps 0.5 m ahead of the camera, in the body frame (x forward, y left, z up), dipped
    // 1°, then into the camera's frame.
    const Eigen::Isometry3d T_cam_body = bodyFromCamera(c.basics.mount.mount()).inverse();
    for (const double y : {0.6, -0.6}) {
      camera::Spot s;
      s.position = T_cam_body * Eigen::Vector3d(c.basics.mount.position_m.x() + 0.5, y, 1.0);
      s.direction = T_cam_body.linear() * Eigen::Vector3d(1.0, 0.0, -0.0175).normalized();
      s.half_angle_deg = 15.0;
      s.intensity = 1.0;
      s.half_distance_m = 35.0;
      l.spots.push_back(s);
    }
  }
  return l;
}

// One frame's images, rendered in render(); the instance ids wait for commit().
struct CameraFrame {
  camera::CameraImages images;
  std::string rgb_png, depth_png, depth_pfm, semantic_png, preview_png;  // made in render()
};

class CameraSensor final : public SensorOf<CameraFrame> {
 public:
  CameraSensor(const SensorSetup& setup, const CameraConfig& c)
      : trajectory_(setup.context.trajectory),
        scene_(setup.context.scene),
        instances_(setup.context.instances),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        index_(setup.index),
        cameras_(setup.count),
        T_body_cam0_(setup.context.T_body_cam0),
        config_(c),
        noise_(setup.context.scenario.seed(), name_ + ".noise"),
        intrinsics_(intrinsics(c)),
        lens_(c.distortion.none() ? nullptr
                                  : std::make_unique<camera::LensRemap>(intrinsics_, c.distortion)),
        lighting_(lighting(c)),
        // Relative to the presets' sunny-16 exposure: 1/100 s, ISO 100, f/16.
        exposure_(c.shutter_s / 0.01 * c.iso / 100.0 * std::pow(16.0 / c.f_number, 2),
                  c.read_noise_dn, c.shot_noise_dn),
        // At night a tunnel is lit as the open line is (the lamps, a faint sky): no shade.
        daylight_(c.daytime == Daytime::kNight ? nullptr : tunnelDaylight(setup)),
        renderer_(rendererOptions(c, lens_ ? lens_->render() : intrinsics_, daylight_)) {
    if (scene_ == nullptr || instances_ == nullptr)
      throw RuntimeError(
          fmt::format("{}: a camera needs the scene (the run did not make it)", setup.path));
    T_body_cam_ = bodyFromCamera(c.basics.mount.mount());
    // KITTI's P1, P2, P3 are rectified: K [I | t], every camera turned as camera 0. A camera
    // turned against camera 0 gets P = K [R | t], which projects correctly, but readers that
    // take K from P's left 3 × 3 (pykitti) get K R instead. Said once, when the run starts.
    const Eigen::Matrix3d R = (T_body_cam_.inverse() * T_body_cam0_).linear();
    if ((R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9)
      logWarn(fmt::format(
          "{}: the camera is turned against camera 0, so calib.txt's P{} is K [R | t], not a "
          "rectified K [I | t]: project with it whole; readers that take K from its left 3 x 3 "
          "(pykitti) get K R",
          setup.path, index_ + 2));
    // The train's own body (train.body) is in the picture of a camera outside it (one looking
    // back along the roof, or down at it), as the box that stops the LiDARs' rays: unlabelled,
    // no instance. A camera inside the box is behind the windscreen and sees out.
    const TrainConfig train = trainSection().read(setup.context.scenario.json());
    if (train.body.enabled) {
      // The box is in the pivots' midpoint's axes, the trajectory's pose the reported point's.
      const Eigen::AlignedBox3d box = train.body.box().translate(-train.reference_point);
      if (!box.contains(T_body_cam_.translation())) {
        auto mesh = std::make_shared<scene::Mesh>();
        mesh->beginPart(scene::cls::kUnlabelled, scene::mat::kPaintedMetal);
        scene::addBox(*mesh, box.min().cast<float>(), box.max().cast<float>());
        body_ = std::move(mesh);
      }
    }
    // Tunnels: the night's lamps and faint light, the day's sky seen through the portals.
    CameraConfig at_night = c;
    at_night.daytime = Daytime::kNight;
    tunnel_lighting_ = lighting(at_night);
    tunnel_lighting_.sky_zenith = lighting_.sky_zenith;
    tunnel_lighting_.sky_horizon = lighting_.sky_horizon;
    // The fog's colour is that of fog lit as under the noon preset (applyFog).
    CameraConfig at_noon = c;
    at_noon.daytime = Daytime::kNoon;
    noon_sky_light_ = skywardLight(lighting(at_noon));
    if (setup.context.route != nullptr)
      for (const track::Block& block : setup.context.route->blocks)
        if (block.type == track::BlockType::kTunnel)
          tunnels_.push_back(block);
    camera_ahead_of_front_m_ = c.basics.mount.position_m.x() + train.reference_point.x() -
                               0.5 * train.vehicle.bogie_spacing_m;
    // The near plane cuts away what is nearer than near_m along the optical axis: for a camera
    // that looks down steeply from low down (an inspection camera) that is the track itself,
    // drawn as nothing (depth 0, class sky). Said once, from the rail-top plane under a level
    // train (the reported point is reference_point above the pivots' midpoint at rail top).
    const double height = T_body_cam_.translation().z() + train.reference_point.z();
    double nearest = std::numeric_limits<double>::infinity();
    for (const double u : {0.0, 0.5 * (c.width - 1), c.width - 1.0})
      for (const double v : {0.0, c.height - 1.0}) {
        const Eigen::Vector3d ray((u - intrinsics_.cx) / intrinsics_.fx,
                                  (v - intrinsics_.cy) / intrinsics_.fy, 1.0);
        const double down = -(T_body_cam_.linear() * ray).z();  // per metre of depth
        if (height > 0.0 && down > 0.0)
          nearest = std::min(nearest, height / down);
      }
    if (nearest < c.near_m)
      logWarn(
          fmt::format("{}: the camera sees the rail-top plane from {:.2f} m along its axis, "
                      "nearer than near_m ({} m): what lies nearer is not drawn (depth 0, "
                      "class sky); lower near_m",
                      setup.path, nearest, c.near_m));
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return kCameraKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override {
    std::vector<std::string> files = sensorFiles(kReadingsCsv, name_);
    if (config_.rgb)
      files.push_back(io::DatasetLayout::imageFolder(index_) + "/");
    if (config_.depth || config_.depth_float)
      files.push_back(io::DatasetLayout::depthFolder(index_) + "/");
    if (config_.semantic)
      files.push_back(io::DatasetLayout::semanticFolder(index_) + "/");
    if (config_.semantic_preview)
      files.push_back(io::DatasetLayout::semanticPreviewFolder(index_) + "/");
    if (config_.instance)
      files.push_back(io::DatasetLayout::instanceFolder(index_) + "/");
    return files;
  }

  // P_{index + 2} (image_{index + 2}) projects points in camera 0's frame (Tr's and poses.txt's)
  // into this camera's image. P0–P3 are always written, as KITTI's readers expect all four:
  // camera 0 also writes P0 and P1, and P3 when it is the only camera.
  std::vector<std::string> calibration() const override {
    const Eigen::Isometry3d T_cam_cam0 = T_body_cam_.inverse() * T_body_cam0_;
    const Eigen::Matrix<double, 3, 4> P = intrinsics_.matrix() * T_cam_cam0.matrix().topRows<3>();
    const auto line = [&](int n) { return kittiCalibLine(fmt::format("P{}", n), P); };
    std::vector<std::string> lines;
    if (index_ == 0) {
      lines.push_back(line(0));
      lines.push_back(line(1));
    }
    lines.push_back(line(index_ + 2));
    if (index_ == 0 && cameras_ == 1)
      lines.push_back(line(3));
    if (lens_) {  // after P and Tr (generate's order): OpenCV's distortion of image_{index + 2}
      const camera::Distortion& d = config_.distortion;
      lines.push_back(fmt::format("D{}: {:.12e} {:.12e} {:.12e} {:.12e} {:.12e}", index_ + 2, d.k1,
                                  d.k2, d.p1, d.p2, d.k3));
    }
    return lines;
  }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    writer_ = &writer;
    csv_ = &writer.appendFile(writer.layout().inSequence(outputs().front()));
    class_pixels_.restore(state);
    if (state.is_null())
      csv_->write("frame,t_ns,objects,triangles\n");
  }

  // Not null even before a frame: a resumed run must not write the CSV header again.
  nlohmann::json state() const override { return class_pixels_.state(); }
  // The pixels per class of the run's semantic images (when the camera makes them): what
  // classes.yaml's content is taken from when there is no LiDAR.
  nlohmann::json summary() const override { return class_pixels_.summary(); }

 private:
  // `k`: the pinhole to render with (larger than the image with a lens, see LensRemap).
  static camera::RendererOptions rendererOptions(
      const CameraConfig& c, const camera::Intrinsics& k,
      const std::shared_ptr<const terrain::TunnelDaylight>& daylight) {
    camera::RendererOptions o;
    if (daylight) {
      o.daylight = [daylight](std::span<const Eigen::Vector3d> points, std::span<float> shares) {
        daylight->shares(points, shares);
      };
      o.shade_meets = [daylight](const scene::Box3d& box) { return daylight->meets(box); };
    }
    o.intrinsics = k;
    o.near_m = c.near_m;
    o.far_m = c.far_m;
    o.fxaa = c.fxaa;
    // Fog needs each pixel's range, so a foggy colour image needs the depth pass too.
    const bool ids = c.semantic || c.semantic_preview || c.instance;
    o.passes = {c.rgb, c.depth || c.depth_float || (c.rgb && c.fog_visibility_m > 0.0), ids, ids};
    return o;
  }

  // Fog by each pixel's range r (Beer–Lambert with Koschmieder's extinction 3.912 / V): the
  // surface's colour fades to the fog's as e^(−βr); the sky, at no range, is the fog's colour.
  // The fog is lit as the scene is: its colour, light grey under the noon preset's sun and sky,
  // scales in linear light with the light a surface facing the sky gets (ambient plus the sun's
  // diffuse share), so night fog is dark and a tunnel's fog as dim as its walls.
  void applyFog(camera::CameraImages& img, const camera::Lighting& lighting) const {
    const double beta = 3.912 / config_.fog_visibility_m;
    const camera::Intrinsics& k = renderer_.options().intrinsics;
    const double lit = skywardLight(lighting) / noon_sky_light_;
    // Koschmieder's blend of the object's light and the fog's, in linear light.
    constexpr std::uint8_t kFog[3] = {200, 204, 208};
    const double fog[3] = {lit * camera::Srgb::toLinear(kFog[0]),
                           lit * camera::Srgb::toLinear(kFog[1]),
                           lit * camera::Srgb::toLinear(kFog[2])};
    for (int v = 0; v < img.height; ++v)
      for (int u = 0; u < img.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * img.width + u;
        const double z = img.depth[i];
        const double x = (u - k.cx) / k.fx, y = (v - k.cy) / k.fy;
        const double keep = z > 0.0 ? std::exp(-beta * z * std::sqrt(1.0 + x * x + y * y)) : 0.0;
        for (int ch = 0; ch < 3; ++ch) {
          std::uint8_t& c = img.rgb[3 * i + ch];
          c = camera::Srgb::fromLinear(keep * camera::Srgb::toLinear(c) + (1.0 - keep) * fog[ch]);
        }
      }
  }

  // Exposure and sensor noise on the colour image of sample k, in linear light (camera::Exposure):
  // the render's light scaled by the exposure (t · ISO / N², relative to sunny 16), then Gaussian
  // noise of variance read² + shot² · value / 255 from the counter-based stream (pixel, sample),
  // clipped at white and encoded back to sRGB.
  void develop(camera::CameraImages& img, std::int64_t k) const {
    if (exposure_.identity())
      return;
    std::array<double, 4> z{};
    for (std::size_t i = 0; i < img.rgb.size(); ++i) {
      if (exposure_.noisy() && i % 4 == 0)
        z = noise_.normal4(i / 4, static_cast<std::uint64_t>(k));
      img.rgb[i] = exposure_(img.rgb[i], z[i % 4]);
    }
  }

  CameraFrame read(std::int64_t k) const override {
    const Eigen::Isometry3d pose = trajectory_.sample(k).pose();
    const Eigen::Isometry3d T = pose * T_body_cam_;
    scene::SceneWindow window = scene_->window(T.translation(), config_.far_m);
    if (body_) {
      // One tile of its own, under an index no scene tile has.
      auto tile = std::make_shared<scene::Tile>();
      tile->index = {std::numeric_limits<std::int32_t>::min(),
                     std::numeric_limits<std::int32_t>::min()};
      tile->origin = pose.translation();
      tile->objects.push_back(
          scene::Object::place(body_, pose.translation(), pose.linear().cast<float>(), 0));
      tile->updateBounds();
      window.tiles.push_back(std::move(tile));
    }
    CameraFrame out;
    // Each surface lit as much by the day as reaches it (a tunnel's bore is in the shade), the
    // fog as it is where the camera is.
    out.images = renderer_.render(window, T, lighting_, daylight_ ? &tunnel_lighting_ : nullptr);
    if (config_.rgb && config_.fog_visibility_m > 0.0)
      applyFog(out.images, lightingAt(trajectory_.sample(k).chainage_m));
    if (lens_)
      out.images = lens_->apply(out.images);
    camera::CameraImages& img = out.images;
    if (config_.rgb) {
      develop(img, k);
      out.rgb_png = io::encodePngRgb8(img.width, img.height, img.rgb);
    }
    if (config_.depth) {
      std::vector<std::uint16_t> depth(img.depth.size());
      for (std::size_t i = 0; i < depth.size(); ++i) {
        const double z = img.depth[i];
        depth[i] = z > 0.0 && z <= config_.depth_max_m
                       ? static_cast<std::uint16_t>(std::min(65535L, std::lround(z * 256.0)))
                       : 0;
      }
      out.depth_png =
          io::encodePngGray16(img.width, img.height, depth, io::PngContent::kMeasurement);
    }
    if (config_.depth_float) {
      // PFM: a text header, then rows bottom to top of little-endian float32 (scale < 0).
      std::string& pfm = out.depth_pfm;
      pfm = fmt::format("Pf\n{} {}\n-1.0\n", img.width, img.height);
      const std::size_t header = pfm.size(), row = 4 * static_cast<std::size_t>(img.width);
      pfm.resize(header + row * img.height);
      for (int v = 0; v < img.height; ++v)
        std::memcpy(pfm.data() + header + row * (img.height - 1 - v),
                    img.depth.data() + static_cast<std::size_t>(v) * img.width, row);
    }
    if (config_.semantic)
      out.semantic_png =
          io::encodePngGray8(img.width, img.height, img.semantic, io::PngContent::kLabels);
    if (config_.semantic_preview) {
      std::vector<std::uint8_t> rgb(3 * img.semantic.size());
      for (std::size_t i = 0; i < img.semantic.size(); ++i) {
        const scene::Rgb c = scene::semanticClass(img.semantic[i]).colour;
        std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
      }
      out.preview_png = io::encodePngRgb8(img.width, img.height, rgb);
    }
    return out;
  }

  void write(std::int64_t k, CameraFrame& f) override {
    const std::int64_t frame = k / (period_ / trajectory_.samplePeriod());
    const io::DatasetLayout& layout = writer_->layout();
    const auto file = [&](const std::string& folder, const char* ext = "png") {
      return layout.inSequence(io::DatasetLayout::frameFile(folder, frame, ext));
    };
    if (config_.rgb)
      writer_->writeFile(file(io::DatasetLayout::imageFolder(index_)), f.rgb_png);
    if (config_.depth)
      writer_->writeFile(file(io::DatasetLayout::depthFolder(index_)), f.depth_png);
    if (config_.depth_float)
      writer_->writeFile(file(io::DatasetLayout::depthFolder(index_), "pfm"), f.depth_pfm);
    if (config_.semantic)
      writer_->writeFile(file(io::DatasetLayout::semanticFolder(index_)), f.semantic_png);
    if (config_.semantic_preview)
      writer_->writeFile(file(io::DatasetLayout::semanticPreviewFolder(index_)), f.preview_png);
    if (config_.instance) {
      // The sequence's ids, numbered as objects first appear in raster order (the LiDARs of
      // the same sample committed theirs before).
      const camera::CameraImages& img = f.images;
      std::vector<std::int32_t> ids(img.instances.size(), -1);
      std::vector<std::uint16_t> pixels(img.object.size());
      for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::int32_t& id = ids[img.object[i]];
        if (id < 0)
          id = instances_->id(img.instances[img.object[i]], img.semantic[i]);
        pixels[i] = static_cast<std::uint16_t>(id);
      }
      writer_->writeFile(
          file(io::DatasetLayout::instanceFolder(index_)),
          io::encodePngGray16(img.width, img.height, pixels, io::PngContent::kLabels));
    }
    for (const std::uint8_t cls : f.images.semantic)
      class_pixels_.add(cls);
    csv_->write(fmt::format("{},{},{},{}\n", frame, k * trajectory_.samplePeriod(),
                            f.images.objects, f.images.triangles));
  }

  // How much daylight reaches each surface, when the route has tunnels (the tubes' sizes are
  // the terrain section's).
  static std::shared_ptr<const terrain::TunnelDaylight> tunnelDaylight(const SensorSetup& setup) {
    if (setup.context.route == nullptr || setup.context.layout == nullptr)
      return nullptr;
    auto d = std::make_shared<const terrain::TunnelDaylight>(
        *setup.context.route, *setup.context.layout,
        terrainSection().read(setup.context.scenario.json()));
    return d->empty() ? nullptr : d;
  }

  // The light where the camera is, for the fog around it (the surfaces are lit by their own
  // share of daylight, TunnelDaylight): in a tunnel, the sun's and the sky's light fade
  // linearly to none 50 m from a portal (a look, not a light-transport model) and the train's
  // headlights are on; outside, the configured lighting as it is.
  camera::Lighting lightingAt(double front_chainage_m) const {
    const double c = front_chainage_m + camera_ahead_of_front_m_;
    double inside = 0.0;  // metres from the nearer portal, 0 outside
    for (const track::Block& b : tunnels_)
      if (c > b.chainage_begin_m && c < b.chainage_end_m)
        inside = std::min(c - b.chainage_begin_m, b.chainage_end_m - c);
    if (inside <= 0.0)
      return lighting_;
    constexpr double kDaylightReach = 50.0;
    const double day = std::max(0.0, 1.0 - inside / kDaylightReach);
    camera::Lighting l = tunnel_lighting_;
    l.sun_intensity = day * lighting_.sun_intensity;
    l.ambient = tunnel_lighting_.ambient + day * (lighting_.ambient - tunnel_lighting_.ambient);
    return l;
  }

  const Trajectory& trajectory_;
  scene::SceneStream* scene_;
  std::shared_ptr<InstanceTable> instances_;
  std::string name_;
  TimeNs period_;
  int index_;
  int cameras_;
  Eigen::Isometry3d T_body_cam0_, T_body_cam_;
  std::shared_ptr<const scene::Mesh> body_;  // the train's body in the reported point's axes
  CameraConfig config_;
  RandomStream noise_;
  camera::Intrinsics intrinsics_;  // the image's (calib.txt's P)
  std::unique_ptr<camera::LensRemap> lens_;
  camera::Lighting lighting_, tunnel_lighting_;
  double noon_sky_light_ = 1.0;           // skywardLight() under the noon preset
  std::vector<track::Block> tunnels_;     // the main track's tunnel blocks
  double camera_ahead_of_front_m_ = 0.0;  // the camera's chainage past the front pivot's
  camera::Exposure exposure_;
  std::shared_ptr<const terrain::TunnelDaylight> daylight_;  // null: no tunnel on the route
  camera::Renderer renderer_;
  io::DatasetWriter* writer_ = nullptr;
  io::AppendFile* csv_ = nullptr;
  ClassCounts class_pixels_{"class_pixels", "pixels"};
};

}  // namespace

scenario::Param declareCamera() {
  return cameraBinding().declare(
      "camera",
      "A camera rendered with VTK (offscreen OpenGL; an X server, or Xvfb started for the run): "
      "KITTI image_N/*.png, depth_N/*.png (uint16 m * 256), semantic_N/*.png (class ids) and "
      "instance_N/*.png (the LiDAR labels' instance ids), one file each per frame.");
}

void checkCamera(const scenario::Json& item, const std::string& path,
                 std::vector<scenario::Problem>& problems) {
  cameraBinding().problems(cameraBinding().read(item), path, problems);
}

std::unique_ptr<Sensor> createCamera(const SensorSetup& setup) {
  return std::make_unique<CameraSensor>(setup, cameraBinding().read(setup.config));
}

Eigen::Isometry3d cameraBodyPose(const scenario::Json& item) {
  return bodyFromCamera(readMount(item));
}

}  // namespace trainsim::sim
