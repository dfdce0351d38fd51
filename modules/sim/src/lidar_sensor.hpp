#pragma once

#include <memory>

#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// sensors.lidars[]: a rotating multi-beam LiDAR on a body mount, cast into the scene.
scenario::Param declareLidar();
std::unique_ptr<Sensor> createLidar(const SensorSetup& setup);
void checkLidar(const scenario::Json& item, const std::string& path,
                std::vector<scenario::Problem>& problems);
/// What lidarWarnings says of the resolved item at `path`.
std::vector<std::string> warnLidar(const scenario::Json& resolved, const scenario::Json& item,
                                   const std::string& path, int index);
/// Checks that the LiDAR item at `path` has no beam leaving its head inside the train's body
/// (train.body).
void checkLidarClearOfTheBody(const scenario::Json& item, const TrainConfig& train,
                              const std::string& path, std::vector<scenario::Problem>& problems);

}  // namespace trainsim::sim
