#pragma once

// One home for TrainSim's frame conventions and shared physical constants. Each convention is
// pinned by a test named after it (tests/unit/core_frames_test.cpp); docs/ARCHITECTURE.md lists
// them. Sources: docs/REFERENCES.md.

#include <numbers>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace trainsim {

/// Standard gravity g_n (CGPM 1901), for design rules and datasheet ranges given "in g".
/// Physical gravity in the truth is WGS-84 normal gravity (inertial/earth.hpp).
inline constexpr double kStandardGravity_m_s2 = 9.80665;
/// Degrees to radians.
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

/// Attitude convention for the body and for every sensor mount (ZYX Tait–Bryan, intrinsic):
///   R = Rz(yaw) · Ry(−pitch) · Rx(roll)
/// in a frame with x forward, y left, z up. Yaw turns x towards y (counter-clockwise seen from
/// above); pitch is positive nose-up (x towards z); roll is positive right side down (y
/// towards z). R maps vectors of the rotated frame into the parent frame (R_parent_child).
Eigen::Matrix3d attitude(double yaw_rad, double pitch_rad, double roll_rad);

/// Where a sensor sits on the carbody: position of its origin relative to the body reference
/// point (train.reference_point) and the attitude of its axes, both in body axes (x forward,
/// y left, z up), angles by attitude(). Every sensor kind reads its mount from the scenario
/// the same way (sim::declareMount / sim::readMount).
struct Mount {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d r_body_sensor = Eigen::Matrix3d::Identity();

  Eigen::Isometry3d T_body_sensor() const;
};

/// KITTI camera axes (x right, y down, z forward) in body axes: R_body_cam, whose columns are
/// camera x = −body y, camera y = −body z, camera z = body x.
Eigen::Matrix3d rotationBodyFromKittiCamera();

/// KITTI velodyne axes (x forward, y left, z up) coincide with body axes: R_body_velo = I.
Eigen::Matrix3d rotationBodyFromKittiVelodyne();

/// KITTI's `Tr` in calib.txt maps points from the velodyne frame into the camera frame:
/// p_cam = Tr · p_velo, i.e. Tr = T_cam_velo = T_body_cam⁻¹ · T_body_velo.
Eigen::Isometry3d kittiTr(const Eigen::Isometry3d& T_body_cam,
                          const Eigen::Isometry3d& T_body_velo);

/// A calib.txt line as KITTI writes one: "`key`: " and the 3 × 4 matrix row by row, each value
/// with 13 significant digits ("Tr: 4.276802385584e-04 -9.999672484946e-01 …").
std::string kittiCalibLine(std::string_view key, const Eigen::Matrix<double, 3, 4>& m);

}  // namespace trainsim
