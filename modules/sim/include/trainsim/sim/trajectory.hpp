#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/core/time.hpp"

namespace trainsim::sim {

/// The train's state at one trajectory sample, in the world frame (ENU at the scenario's
/// geodetic anchor, double precision).
struct TrajectorySample {
  TimeNs t_ns = 0;
  double chainage_m = 0.0;  ///< front pivot, horizontal chainage on the main track
  double distance_m = 0.0;  ///< front pivot, distance along the track in 3D (odometer truth)
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();  ///< body reference point
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_body = Eigen::Vector3d::Zero();      ///< angular velocity in body axes, rad/s
  Eigen::Vector3d alpha_body = Eigen::Vector3d::Zero();  ///< angular acceleration, body axes
  double speed_m_s = 0.0;                                ///< along the track
  double accel_m_s2 = 0.0;  ///< along the track (dv/dt of the front pivot)
};

/// Ground truth sampled at the fixed period T_S: sample k is at t = k * T_S. The movement
/// system binds every sensor reading to one of these samples (paper, Movement System).
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual TimeNs samplePeriod() const = 0;
  virtual std::int64_t sampleCount() const = 0;
  /// Sample k, 0 <= k < sampleCount(). Must be a pure function of k (thread-safe).
  virtual TrajectorySample sample(std::int64_t k) const = 0;
};

}  // namespace trainsim::sim
