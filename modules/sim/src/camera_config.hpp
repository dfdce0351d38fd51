#pragma once
// Private to the sim module: sensors.cameras[] as the camera sensor reads it (the binding that
// declares, checks and reads it) and what follows from it: the intrinsics, the lighting and the
// camera's pose on the body.
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/camera/lens.hpp"
#include "trainsim/camera/renderer.hpp"
#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/scenario/binding.hpp"
#include "trainsim/sim/sensor_params.hpp"

namespace trainsim::sim {

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
  double fog_visibility_m = 0.0, fog_height_m = 100.0;
  bool headlights = false;
  double shutter_s = 0.01, f_number = 16.0, iso = 100.0;
  double read_noise_dn = 0.0, shot_noise_dn = 0.0;
  bool fxaa = true;
};

/// The binding of sensors.cameras[] (declaration, checks, reading).
const scenario::Binding<CameraConfig>& cameraBinding();

/// The camera's pose on the body: the mount, then KITTI's camera axes.
Eigen::Isometry3d bodyFromCamera(const Mount& mount);

/// The pinhole intrinsics the configuration gives (fx from the field of view when it is 0).
camera::Intrinsics intrinsics(const CameraConfig& c);

/// The light a surface facing the sky gets: the sky's (ambient) and the sun's diffuse share.
double skywardLight(const camera::Lighting& l);

/// The sun, sky and lamps of the configuration's daytime (sensors-reference.md 7.5).
camera::Lighting lighting(const CameraConfig& c);

/// The pinhole it renders with: intrinsics(c), or with a lens the larger one LensRemap draws.
camera::Intrinsics renderIntrinsics(const CameraConfig& c);

/// Settings that are valid but may not do what is meant (a camera turned against camera 0, a
/// view past the terrain's edge, a near plane cutting the track), for the camera `index` at
/// `path` in the resolved scenario: what validate and the run's start say.
std::vector<std::string> cameraWarnings(const CameraConfig& c, const scenario::Json& resolved,
                                        const std::string& path, int index);

}  // namespace trainsim::sim
