#pragma once

#include <memory>

#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// sensors.imus[]: 9-axis IMU (accelerometer, gyroscope, magnetometer) on a body mount.
scenario::Param declareImu();
std::unique_ptr<Sensor> createImu(const SensorSetup& setup);
void checkImu(const scenario::Json& item, const std::string& path,
              std::vector<scenario::Problem>& problems);

}  // namespace trainsim::sim
