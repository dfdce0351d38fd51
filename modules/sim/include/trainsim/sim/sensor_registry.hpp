#pragma once

#include <memory>
#include <span>
#include <vector>

#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// Sensor::kind() of the registered kinds, as the manifest lists them (the studio's views are
/// registered by these).
inline constexpr const char* kImuKind = "imu";
inline constexpr const char* kGnssKind = "gnss";
inline constexpr const char* kOdometerKind = "odometer";
inline constexpr const char* kBaliseReaderKind = "balise_reader";
inline constexpr const char* kLidarKind = "lidar";
inline constexpr const char* kCameraKind = "camera";

/// One kind of sensor: its scenario declaration and its factory. The scenario holds a list
/// of sensors of each kind under `sensors.<key>[]` (e.g. `sensors.imus[]`).
struct SensorKind {
  const char* key;          ///< array name under "sensors", plural: "imus", "lidars"
  const char* description;  ///< one line for the schema table
  /// The declaration every item of sensors.<key>[] follows (from the kind's binding).
  scenario::Param (*declare)();
  std::unique_ptr<Sensor> (*create)(const SensorSetup& setup);
  /// The checks across the fields of one resolved item (its binding's), at JSON path `path`.
  void (*check)(const scenario::Json& item, const std::string& path,
                std::vector<scenario::Problem>& problems);
  /// What is valid but may not be meant in the resolved item at `path` (the kind's `index`th
  /// sensor) of the resolved scenario: one line each, said by validate and at a run's start.
  /// Null for kinds with nothing to say.
  std::vector<std::string> (*warn)(const scenario::Json& resolved, const scenario::Json& item,
                                   const std::string& path, int index);
  /// The files a sensor of this kind writes in the sequence folder, with "{}" for its name
  /// ("{}.csv", "{}_truth.csv"); the schema checks that no two sensors share a file.
  std::span<const char* const> files;
  /// Frame-synchronous kinds (LiDARs, cameras) record one reading per dataset frame: their
  /// period must equal dataset.frame_period_ns, so KITTI's readers pair reading i with line i
  /// of times.txt and poses.txt.
  bool frame_synchronous = false;
};

/// The registration table (sensor_registry.cpp), in the order sensors are created and run.
std::span<const SensorKind> sensorKinds();

/// The context shared by the sensors of one run (sensor.hpp). `route` and `layout` may be null
/// (synthetic trajectories).
SensorContext makeSensorContext(const scenario::Scenario& scenario, const Trajectory& trajectory,
                                const track::Route* route = nullptr,
                                const track::Layout* layout = nullptr);

/// Camera 0 → body in a resolved scenario: the frame of KITTI's Tr and poses.txt. The first
/// camera's mount with KITTI's camera axes (x right, y down, z forward); without a camera, those
/// axes at the body's reference point.
Eigen::Isometry3d referenceCameraPose(const scenario::Json& resolved);

/// What every sensor's settings do that may not be meant (SensorKind::warn), in table order,
/// then LiDARs and cameras given different fog.
std::vector<std::string> sensorWarnings(const scenario::Json& resolved);

/// Creates every sensor configured in the context's scenario, kind by kind in table order,
/// after logging sensorWarnings() as warnings.
/// The sensors keep references into `context`, which must outlive them.
std::vector<std::unique_ptr<Sensor>> createSensors(const SensorContext& context);

/// The item of the sensor named `name` in a resolved scenario document, of any kind; null if
/// there is none.
const scenario::Json* findSensorConfig(const scenario::Json& scenario, const std::string& name);

/// Adds the `sensors` section: an array per kind, and the name check below.
void addSensorsSection(scenario::Schema& schema);

/// Whether the resolved scenario has a frame-synchronous sensor (a LiDAR or a camera): only
/// then does the run make the environment and its scene stream.
bool needsScene(const scenario::Json& resolved);
/// Whether sensors.<key> lists any sensor.
bool hasSensors(const scenario::Json& resolved, std::string_view key);

/// Checks that every frame-synchronous sensor's period equals dataset.frame_period_ns.
void checkFrameSynchronous(const scenario::Json& resolved,
                           std::vector<scenario::Problem>& problems);

/// Checks sensor names across all kinds: each unique (naming both JSON paths when two clash),
/// safe as a file name, and no two sensors writing the same file. Appends problems.
void checkSensorNames(const scenario::Json& resolved, std::vector<scenario::Problem>& problems);

}  // namespace trainsim::sim
