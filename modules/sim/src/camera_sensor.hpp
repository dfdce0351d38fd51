#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// sensors.cameras[]: a camera on a body mount, rendered into the scene with VTK.
scenario::Param declareCamera();
std::unique_ptr<Sensor> createCamera(const SensorSetup& setup);
void checkCamera(const scenario::Json& item, const std::string& path,
                 std::vector<scenario::Problem>& problems);
/// What cameraWarnings says of the resolved item at `path`, the camera `index`.
std::vector<std::string> warnCamera(const scenario::Json& resolved, const scenario::Json& item,
                                    const std::string& path, int index);
/// Camera → body of a resolved sensors.cameras[] item: its mount with KITTI's camera axes (x
/// right, y down, z forward).
Eigen::Isometry3d cameraBodyPose(const scenario::Json& item);

}  // namespace trainsim::sim
