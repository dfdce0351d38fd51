#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace trainsim::io {

/// One LiDAR return as PCL's point cloud file has it: the fields of Velodyne's ROS driver
/// (x y z intensity ring time, the PointXYZIRT that LIO-SAM and friends read) and PCL's
/// `label` (as pcl::PointXYZL), here SemanticKITTI's class | instance << 16.
struct PcdPoint {
  float x = 0.0f, y = 0.0f, z = 0.0f;
  float intensity = 0.0f;
  /// 0 = the lowest laser, as Velodyne's ROS driver numbers them (LidarPoint::ring and
  /// point_info count from the highest, as KITTI's point order goes).
  std::uint16_t ring = 0;
  float time = 0.0f;  ///< firing time after the scan's start, s
  std::uint32_t label = 0;
};

/// A PCD v0.7 file of `points` (header from PCL 1.13's writer, `DATA binary`, 26 bytes a point
/// packed in the field order above), unorganised (height 1), viewpoint at the sensor: PCL,
/// Open3D and CloudCompare read it. Throws RuntimeError if PCL fails.
std::string encodePcd(std::span<const PcdPoint> points);

}  // namespace trainsim::io
