#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "trainsim/core/time.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/trajectory.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::sim {

/// A simulated sensor driven by the movement system. It fires at every trajectory sample whose
/// time is a multiple of its period (itself a multiple of T_S, checked by the scenario schema)
/// and writes its output through the DatasetWriter.
///
/// Resume contract: everything a sensor draws at a sample must be a pure function of the
/// scenario, the seed and the sample index (use RandomStream keyed by the sample index), or be
/// carried in state(), which the movement system stores at each checkpoint and hands back to
/// begin() when a run is resumed.
class Sensor {
 public:
  virtual ~Sensor() = default;

  /// Unique name used in logs, the manifest and random stream names ("imu0", "frames").
  virtual std::string name() const = 0;
  /// Registry kind ("imu", "lidar"), or "frames" for the built-in frame clock.
  virtual std::string kind() const = 0;
  virtual TimeNs period() const = 0;

  /// Opens the sensor's files. `state` is null for a fresh run, or what state() returned at
  /// the checkpoint being resumed.
  virtual void begin(io::DatasetWriter& writer, const nlohmann::json& state) = 0;
  /// Produces the reading of trajectory sample `k` (t = k * T_S).
  virtual void capture(std::int64_t k, const TrajectorySample& sample) = 0;
  /// The state needed to continue after the last captured sample (null if stateless).
  virtual nlohmann::json state() const { return nullptr; }
  /// Closes the sensor after the last sample of a complete run.
  virtual void end() {}
};

/// What a sensor factory gets: the resolved scenario, the sensor's own resolved section
/// (e.g. sensors.imus[0]) and its index within its kind.
struct SensorSetup {
  const scenario::Scenario& scenario;
  const scenario::Json& config;
  std::size_t index;
  /// The planned main route (tunnels for GNSS, balise placement), or null when a sensor runs
  /// on a synthetic trajectory.
  const track::Route* route = nullptr;
};

}  // namespace trainsim::sim
