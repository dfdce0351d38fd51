#include "trainsim/sim/sensor_registry.hpp"

#include <fmt/format.h>

#include <array>

namespace trainsim::sim {

// The sensor registration table: one line per sensor kind.
//
// How to add a sensor kind:
//   1. Implement trainsim::sim::Sensor (sensor.hpp) in the module that owns the physics, e.g.
//      modules/sensors/src/imu.cpp, respecting the resume contract stated there.
//   2. Give it a `scenario::Param declareX()` (an object(...) with the sensor's parameters,
//      units in the names, the period declared with .multipleOf("trajectory.sample_period_ns"))
//      and a `std::unique_ptr<Sensor> createX(const SensorSetup&)`.
//   3. Add one line below: {"<plural key>", "<one-line description>", &declareX, &createX}.
// The schema (sensors.<key>[]), validation, `trainsim schema`, docs/SCENARIO.md, the studio's
// panels and the run loop pick the new kind up from this table; nothing else changes.
//
// The list is empty until the first sensor module lands (inertial sensors, issue #4). The
// frame clock that writes times.txt and poses.txt is not a registered kind: every dataset
// has exactly one (frame_clock.hpp).
namespace {
constexpr std::array<SensorKind, 0> kSensorKinds = {};
}  // namespace

std::span<const SensorKind> sensorKinds() {
  return kSensorKinds;
}

std::vector<std::unique_ptr<Sensor>> createSensors(const scenario::Scenario& scenario) {
  std::vector<std::unique_ptr<Sensor>> sensors;
  for (const SensorKind& kind : sensorKinds()) {
    const std::string path = fmt::format("sensors.{}", kind.key);
    const scenario::Json& list = scenario.at(path);
    for (std::size_t i = 0; i < list.size(); ++i) {
      sensors.push_back(kind.create(SensorSetup{scenario, list[i], i}));
    }
  }
  return sensors;
}

}  // namespace trainsim::sim
