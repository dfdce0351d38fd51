#pragma once
// A sensor standing still, for the LiDAR's tests.
#include <Eigen/Geometry>

#include "trainsim/lidar/lidar.hpp"

namespace trainsim::test {

/// The pose of a sensor standing at `at`, axes along the world's, whatever the time.
inline lidar::PoseAt fixedPose(const Eigen::Vector3d& at) {
  return [at](double) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = at;
    return T;
  };
}

}  // namespace trainsim::test
