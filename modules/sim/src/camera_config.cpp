#include "camera_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "trainsim/sim/config.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

namespace units = scenario::units;
constexpr scenario::Unit kM = units::si("m");

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

}  // namespace

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
             "Horizontal field of view, when fx is 0 (square pixels: fy = fx; the principal "
             "point is cx, cy, the image's centre where they are 0)")
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
              "Write depth_N/*.pfm, with or without depth: float32 metres along the optical "
              "axis, 0 for nothing drawn (not clipped at depth_max_m; Portable Float Map, which "
              "OpenCV's imread reads)");
    b.boolean("semantic", &C::semantic, "Write semantic_N/*.png: uint8 class id per pixel");
    b.boolean("semantic_preview", &C::semantic_preview,
              "Write semantic_rgb_N/*.png, with or without semantic: the semantic image in the "
              "classes' colours (the dataset's classes.yaml color_map, from "
              "resources/classes.json), to look at");
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
             "Meteorological visibility of fog at the train (2 % contrast, Koschmieder: "
             "extinction 3.912 / visibility), applied along each pixel's ray through a fog "
             "layer thinning with height (fog_height_m): the sky is veiled as much as the "
             "layer's depth along the ray; the fog lit as the scene is, and never brighter than "
             "its sky's horizon (dark at night); 0: clear")
        .range(0, 100000);
    b.number("fog_height_m", &C::fog_height_m, kM,
             "The fog's scale height: its extinction falls by e for every this many metres "
             "above the camera (and stays the visibility's below it), so a ray rising at "
             "elevation e crosses fog_height_m / sin e of it: a thin ground fog leaves the "
             "zenith clear, a haze hundreds of metres deep greys the whole sky. Default "
             "[unverified]: radiation fog is some tens to a few hundred metres deep")
        .range(1, 100000);
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
      // Pixels at most 4 times as wide as tall or as tall as wide (square pixels have fy = fx,
      // anamorphic lenses reach 2): beyond that the numbers are a typing slip, not a camera.
      if (c.fx > 0.0 && c.fy > 0.0 && (c.fy > 4.0 * c.fx || c.fx > 4.0 * c.fy))
        out.push_back({at(c.fy), fmt::format("is {:.3g} times fx ({:.4g} px): fy / fx must lie "
                                             "within 1/4 ... 4 (1 for square pixels)",
                                             c.fy / c.fx, c.fx)});
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
camera::Intrinsics renderIntrinsics(const CameraConfig& c) {
  const camera::Intrinsics k = intrinsics(c);
  return c.distortion.none() ? k : camera::LensRemap(k, c.distortion).render();
}

std::vector<std::string> cameraWarnings(const CameraConfig& c, const scenario::Json& resolved,
                                        const std::string& path, int index) {
  std::vector<std::string> out;
  const Eigen::Isometry3d T_body_cam = bodyFromCamera(c.basics.mount.mount());
  // KITTI's P1, P2, P3 are rectified: K [I | t], every camera turned as camera 0. A camera
  // turned against camera 0 gets P = K [R | t], which projects correctly, but readers that
  // take K from P's left 3 × 3 (pykitti) get K R instead.
  const Eigen::Matrix3d R = (T_body_cam.inverse() * referenceCameraPose(resolved)).linear();
  if ((R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9)
    out.push_back(fmt::format(
        "{}: the camera is turned against camera 0, so calib.txt's P{} is K [R | t], not a "
        "rectified K [I | t]: project with it whole; readers that take K from its left 3 x 3 "
        "(pykitti) get K R",
        path, index + 2));
  // The ground exists within terrain.tile_margin_m of a track: a camera that sees farther
  // from its axis (looking along the track) or from itself (looking across it) can see where
  // it ends, and what lies beyond comes out as sky, below the horizon.
  const double sideways = c.far_m * std::max(1.0, renderIntrinsics(c).widestSideways());
  if (const double margin = terrainSection().read(resolved).tile_margin_m; sideways > margin)
    out.push_back(fmt::format(
        "{}: at draw_distance_m {} m the picture reaches {:.0f} m from its axis, past the "
        "terrain, which ends terrain.tile_margin_m {} m from the tracks: the ground's edge can "
        "be in view, and the pixels beyond it are labelled sky; raise terrain.tile_margin_m to "
        "{:.0f} m",
        path, c.far_m, sideways, margin, std::ceil(sideways)));
  // The near plane cuts away what is nearer than near_m along the optical axis: for a camera
  // that looks down steeply from low down (an inspection camera) that is the track itself,
  // drawn as nothing (depth 0, class sky). Judged from the rail-top plane under a level train
  // (the reported point is reference_point above the pivots' midpoint at rail top).
  const TrainConfig train = trainSection().read(resolved);
  const camera::Intrinsics k = intrinsics(c);
  const double height = T_body_cam.translation().z() + train.reference_point.z();
  double nearest = std::numeric_limits<double>::infinity();
  for (const double u : {0.0, 0.5 * (c.width - 1), c.width - 1.0})
    for (const double v : {0.0, c.height - 1.0}) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const double down = -(T_body_cam.linear() * ray).z();  // per metre of depth
      if (height > 0.0 && down > 0.0)
        nearest = std::min(nearest, height / down);
    }
  if (nearest < c.near_m)
    out.push_back(
        fmt::format("{}: the camera sees the rail-top plane from {:.2f} m along its axis, "
                    "nearer than near_m ({} m): what lies nearer is not drawn (depth 0, "
                    "class sky); lower near_m",
                    path, nearest, c.near_m));
  return out;
}

}  // namespace trainsim::sim
