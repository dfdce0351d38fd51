#pragma once

#include <any>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/time.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/scene/scene.hpp"
#include "trainsim/sim/trajectory.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::lidar {
class RayWorld;
}

namespace trainsim::sim {

class InstanceTable;

/// What a sensor's render() computed for one reading, handed to its commit(): any movable,
/// copyable value (a struct of truth values, a point cloud, an image).
using Reading = std::any;

/// A simulated sensor driven by the run loop (movement.hpp). It fires at every trajectory
/// sample k whose time k * T_S is a multiple of its period (itself a multiple of T_S, checked
/// by the scenario schema). Each reading is made in two steps:
///
///  - render(k) computes the reading from the trajectory and the sensor's context. It must be
///    pure and thread-safe: the run loop calls it for several samples and sensors at once, on
///    any of its worker threads and in any order. This is where the heavy work goes (ray
///    casting, rendering, truth kinematics).
///  - commit(k, reading) runs on one thread at a time, in sample order and, within a sample,
///    in sensor order. It applies whatever depends on earlier readings (Gauss–Markov states,
///    encoders, random walks) and writes the output through the DatasetWriter.
///
/// So the output bytes never depend on the number of threads, and writing overlaps computing.
///
/// Resume contract: everything commit() draws must be a pure function of the scenario, the
/// seed and the sample index (RandomStream keyed by the index), or be carried in state(),
/// which the run loop stores at each checkpoint and hands back to begin() when resuming.
class Sensor {
 public:
  virtual ~Sensor() = default;

  /// Unique name used for files, logs, the manifest and random stream names ("imu", "frames").
  virtual std::string name() const = 0;
  /// Registry kind ("imu", "lidar"), or "frames" for the built-in frame clock.
  virtual std::string kind() const = 0;
  virtual TimeNs period() const = 0;
  /// The files the sensor writes, relative to the sequence folder; the first holds its
  /// readings. The manifest lists them, and the studio finds them there.
  virtual std::vector<std::string> outputs() const = 0;

  /// Opens the sensor's files. `state` is null for a fresh run, or what state() returned at
  /// the checkpoint being resumed.
  virtual void begin(io::DatasetWriter& writer, const nlohmann::json& state) = 0;
  /// The reading of trajectory sample k (t = k * T_S). Pure and thread-safe (see above).
  virtual Reading render(std::int64_t k) const = 0;
  /// Writes the reading of sample k; called in sample order after begin().
  virtual void commit(std::int64_t k, Reading& reading) = 0;
  /// The state needed to continue after the last committed sample (null if stateless).
  virtual nlohmann::json state() const { return nullptr; }
  /// Closes the sensor after the last sample of a complete run.
  virtual void end() {}
  /// Lines the sensor adds to the sequence's calib.txt ("Tr: …" for the first LiDAR), none by
  /// default.
  virtual std::vector<std::string> calibration() const { return {}; }
  /// What the manifest records about the whole run beyond the reading count (a LiDAR's point
  /// and class counts); null by default. Valid after the last commit, resume included.
  virtual nlohmann::json summary() const { return nullptr; }
};

/// A Sensor whose readings are of type R: implement read(k) (pure) and write(k, R&).
template <typename R>
class SensorOf : public Sensor {
 public:
  Reading render(std::int64_t k) const final { return Reading(read(k)); }
  void commit(std::int64_t k, Reading& reading) final { write(k, std::any_cast<R&>(reading)); }

 protected:
  /// Pure and thread-safe: the reading of sample k.
  virtual R read(std::int64_t k) const = 0;
  /// In sample order: applies sequential state and writes.
  virtual void write(std::int64_t k, R& reading) = 0;
};

/// What the sensors of one run share, built once per run (sensor_registry.hpp,
/// makeSensorContext) instead of by each sensor: the scenario, the geodetic anchor, the
/// trajectory, the planned route and layout (null when a sensor runs on a synthetic
/// trajectory), and what the perception sensors share: the scene stream, Embree's world and the
/// sequence's instance table (null unless a LiDAR or a camera needs them: a run pays for no
/// scene it does not use). The scene stream and the ray world are thread-safe, so render() may
/// use them from any thread; the instance table is for commit() only.
struct SensorContext {
  const scenario::Scenario& scenario;
  GeodeticAnchor anchor;
  const Trajectory& trajectory;
  const track::Route* route = nullptr;
  const track::Layout* layout = nullptr;
  scene::SceneStream* scene = nullptr;
  std::shared_ptr<lidar::RayWorld> rays;
  std::shared_ptr<InstanceTable> instances;
  /// Camera 0 → body: the frame of KITTI's Tr and poses.txt (the first camera's mount with
  /// KITTI's camera axes; without a camera, those axes at the body's reference point).
  Eigen::Isometry3d T_body_cam0 = Eigen::Isometry3d::Identity();
  /// The run's cancel flag (optional), for sensors whose one reading can take long (a LiDAR
  /// scan of many sub-rays) to poll within it.
  const std::atomic<bool>* cancel = nullptr;
};

/// What a sensor factory gets: the run's context, the sensor's own resolved section (e.g.
/// sensors.imus[0]) and its JSON path (for messages).
struct SensorSetup {
  const SensorContext& context;
  const scenario::Json& config;
  std::string path;
  int index = 0;  ///< position in its kind's list (the LiDAR's velodyne_N folder, …)
  int count = 1;  ///< sensors of its kind in the scenario
};

}  // namespace trainsim::sim
