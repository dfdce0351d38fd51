#pragma once

#include <memory>
#include <span>
#include <vector>

#include "trainsim/scenario/param.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// One kind of sensor: its scenario declaration and its factory. The scenario holds a list
/// of sensors of each kind under `sensors.<key>[]` (e.g. `sensors.imus[]`).
struct SensorKind {
  const char* key;          ///< array name under "sensors", plural: "imus", "lidars"
  const char* description;  ///< one line for the schema table
  /// The declaration every item of sensors.<key>[] follows. Periods use
  /// `.multipleOf("trajectory.sample_period_ns")`.
  scenario::Param (*declare)();
  std::unique_ptr<Sensor> (*create)(const SensorSetup& setup);
};

/// The registration table (sensor_registry.cpp), in the order sensors are created and run.
std::span<const SensorKind> sensorKinds();

/// Creates every sensor configured in a resolved scenario, kind by kind in table order.
std::vector<std::unique_ptr<Sensor>> createSensors(const scenario::Scenario& scenario,
                                                   const track::Route* route = nullptr);

}  // namespace trainsim::sim
