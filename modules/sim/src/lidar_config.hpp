#pragma once
// Private to the sim module: sensors.lidars[] as the LiDAR sensor reads it (the binding that
// declares, checks and reads it) and what follows from it: the scan pattern, the scanner's
// parameters and the sensor's pose on the body.
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/scenario/binding.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/sensor_params.hpp"

namespace trainsim::sim {

enum class LidarModel { kHdl64, kVlp16, kHdl32, kVlp32c, kOs1_64, kOs1_128, kUniform };
constexpr EnumName<LidarModel> kLidarModelNames[] = {
    {LidarModel::kHdl64, "hdl64"},    {LidarModel::kVlp16, "vlp16"},
    {LidarModel::kHdl32, "hdl32"},    {LidarModel::kVlp32c, "vlp32c"},
    {LidarModel::kOs1_64, "os1_64"},  {LidarModel::kOs1_128, "os1_128"},
    {LidarModel::kUniform, "uniform"}};
constexpr std::span<const EnumName<LidarModel>> enumNames(LidarModel) {
  return kLidarModelNames;
}

// What the intensity channel holds.
enum class IntensityQuantity { kReflectivity, kRaw };
constexpr EnumName<IntensityQuantity> kIntensityQuantityNames[] = {
    {IntensityQuantity::kReflectivity, "reflectivity"}, {IntensityQuantity::kRaw, "raw"}};
constexpr std::span<const EnumName<IntensityQuantity>> enumNames(IntensityQuantity) {
  return kIntensityQuantityNames;
}

enum class ReturnMode { kStrongest, kLast, kDual };
constexpr EnumName<ReturnMode> kReturnModeNames[] = {{ReturnMode::kStrongest, "strongest"},
                                                     {ReturnMode::kLast, "last"},
                                                     {ReturnMode::kDual, "dual"}};
constexpr std::span<const EnumName<ReturnMode>> enumNames(ReturnMode) {
  return kReturnModeNames;
}

enum class IntensityScaleName { kUnit, kVlp16 };
constexpr EnumName<IntensityScaleName> kIntensityScaleNames[] = {
    {IntensityScaleName::kUnit, "unit"}, {IntensityScaleName::kVlp16, "vlp16"}};
constexpr std::span<const EnumName<IntensityScaleName>> enumNames(IntensityScaleName) {
  return kIntensityScaleNames;
}

struct UniformConfig {
  int channels = 64;
  double fov_up_rad = 2.0 * kRadPerDeg;
  double fov_down_rad = -24.8 * kRadPerDeg;
};

// sensors.lidars[]
struct LidarConfig {
  SensorBasics basics{"lidar", 100'000'000, {Eigen::Vector3d(10.0, 0.0, 4.0)}};
  LidarModel model = LidarModel::kHdl64;
  double rotation_hz = 10.0;
  int columns = 0;
  double horizontal_fov_rad = 2.0 * std::numbers::pi;  // the azimuth window
  UniformConfig uniform;
  double range_min_m = 0.0, range_max_m = 0.0;  // 0: the device's
  double range_sigma_m = -1.0;                  // -1: the device's
  double range_sigma_per_m = 0.0;
  double dropout = 0.0;
  double intensity_threshold = 0.0;
  double range_10_percent_m = 0.0;
  IntensityQuantity intensity = IntensityQuantity::kReflectivity;
  IntensityScaleName scale = IntensityScaleName::kUnit;
  bool motion_distortion = true;
  bool motion_compensated = true;
  bool point_info = true;
  bool pcd = false;
  int sub_rays = 1;
  double divergence_rad = 0.00225;
  double echo_separation_m = 0.3;
  ReturnMode returns = ReturnMode::kStrongest;
  double fog_visibility_m = 0.0, fog_height_m = 100.0, fog_overlap_m = 10.0;
};

/// The preset's name in lidars.json and in messages.
std::string_view presetName(LidarModel m);

/// The scan pattern `c` asks for, before the scenario's range limits.
lidar::ScanPattern devicePattern(const LidarConfig& c);

/// The binding of sensors.lidars[] (declaration, checks, reading).
const scenario::Binding<LidarConfig>& lidarBinding();

/// The sensor's pose in body axes with KITTI's Velodyne axes (x forward, y left, z up).
Eigen::Isometry3d bodyFromSensor(const Mount& mount);

/// The LiDAR's pose in the body's box axes (the mount is relative to the reported point, the
/// box to the pivots' midpoint).
Eigen::Isometry3d poseOnBody(const Mount& mount, const TrainConfig& train);

/// Why a LiDAR of `pattern` at `pose` (poseOnBody) cannot be: empty unless a beam leaves its
/// head inside the body (its origin may stand on the roof: a preset's beams leave the head above
/// it).
std::string insideTheBody(const Eigen::Isometry3d& pose, const lidar::ScanPattern& pattern,
                          const TrainConfig& train);

/// The scanner's parameters for `c` on `train` (the item at `path`, for messages).
lidar::LidarParams scannerParams(const LidarConfig& c, const TrainConfig& train,
                                 const std::string& path);

/// Settings that are valid but do not do what they seem to (dual returns from one ray a pulse,
/// sub-rays without divergence, fog without a detection limit, ranges beyond the device's):
/// what validate and the run's start say, for the LiDAR at `path`.
std::vector<std::string> lidarWarnings(const LidarConfig& c, const std::string& path);

}  // namespace trainsim::sim
