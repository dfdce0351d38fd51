#include "trainsim/sim/sensor_registry.hpp"

#include <fmt/format.h>

#include <array>

#include "imu_sensor.hpp"
#include "positioning_sensors.hpp"

namespace trainsim::sim {

// The sensor registration table: one line per sensor kind.
//
// How to add a sensor kind:
//   1. Put the physics in a module below sim (e.g. modules/inertial) and implement
//      trainsim::sim::Sensor (sensor.hpp) as a thin adapter in modules/sim/src (e.g.
//      imu_sensor.cpp), respecting the resume contract stated there.
//   2. Give it a `scenario::Param declareX()` (an object(...) with the sensor's parameters,
//      units in the names, the period declared with .multipleOf("trajectory.sample_period_ns"))
//      and a `std::unique_ptr<Sensor> createX(const SensorSetup&)`.
//   3. Add one line below: {"<plural key>", "<one-line description>", &declareX, &createX}.
// The schema (sensors.<key>[]), validation, `trainsim schema`, docs/SCENARIO.md, the studio's
// panels and the run loop pick the new kind up from this table; nothing else changes.
//
// The frame clock that writes times.txt and poses.txt is not a registered kind: every
// dataset has exactly one (frame_clock.hpp).
namespace {
constexpr std::array<SensorKind, 4> kSensorKinds = {
    SensorKind{"imus", "9-axis IMUs (accelerometer, gyroscope, magnetometer)", &declareImu,
               &createImu},
    SensorKind{"gnss_receivers", "GNSS receivers", &declareGnss, &createGnss},
    SensorKind{"odometers", "Wheel odometers", &declareOdometer, &createOdometer},
    SensorKind{"balise_readers", "Balise readers (and the balise groups they read)",
               &declareBaliseReader, &createBaliseReader},
};
}  // namespace

std::span<const SensorKind> sensorKinds() {
  return kSensorKinds;
}

std::vector<std::unique_ptr<Sensor>> createSensors(const scenario::Scenario& scenario,
                                                   const track::Route* route) {
  std::vector<std::unique_ptr<Sensor>> sensors;
  for (const SensorKind& kind : sensorKinds()) {
    const std::string path = fmt::format("sensors.{}", kind.key);
    const scenario::Json& list = scenario.at(path);
    for (std::size_t i = 0; i < list.size(); ++i) {
      sensors.push_back(kind.create(SensorSetup{scenario, list[i], i, route}));
    }
  }
  return sensors;
}

}  // namespace trainsim::sim
