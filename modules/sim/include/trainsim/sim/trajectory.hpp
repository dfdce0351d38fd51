#pragma once

#include <cstdint>
#include <functional>
#include <vector>

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

  /// Body → world: the body's attitude at its reference point.
  Eigen::Isometry3d pose() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_world_body.toRotationMatrix();
    T.translation() = p_world;
    return T;
  }
};

/// Ground truth: the train's state at any time in closed form, and the fixed sample clock
/// T_S that binds sensor readings to it (paper, Movement System): sample k is at t = k * T_S.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual TimeNs samplePeriod() const = 0;
  virtual std::int64_t sampleCount() const = 0;
  /// The state at time t (integer ns), evaluated in closed form, not interpolated between
  /// samples; frame sensors ask for the pose at each firing instant within a frame. Times
  /// outside [0, (sampleCount() - 1) * T_S] give the state at the nearer end. Pure and
  /// thread-safe.
  virtual TrajectorySample at(TimeNs t) const = 0;

  /// Times strictly inside (t0, t1), sorted, where the motion is not smooth: a derivative of
  /// the position or the attitude may jump there (an element of the track starts under a
  /// bogie, a motion segment changes its jerk). Quadrature over an interval splits there
  /// (intervalNodes). None by default.
  virtual std::vector<TimeNs> breakpoints(TimeNs /*t0*/, TimeNs /*t1*/) const { return {}; }

  /// Sample k, 0 <= k < sampleCount(): at(k * T_S), bit for bit.
  TrajectorySample sample(std::int64_t k) const { return at(k * samplePeriod()); }
  /// Time of the last sample.
  TimeNs endTime() const { return (sampleCount() - 1) * samplePeriod(); }
};

/// Quadrature nodes over [t0, t1]: three-point Gauss–Legendre on each smooth piece between the
/// trajectory's breakpoints, so the integral of any quantity of the motion is exact to the
/// piece's sixth derivative (about 1e-20 relative for a 10 ms piece of train motion) even
/// where a rate or an acceleration steps. Calls node(t, weight_s) with the weights in seconds
/// summing to t1 − t0; nodes are rounded to the nanosecond. Calls breakpoint(t) for each
/// breakpoint inside, where a quantity whose derivative jumps must add the jump's impulse (a
/// step of the roll rate moves a point off the roll axis with a step in velocity).
void intervalNodes(const Trajectory& trajectory, TimeNs t0, TimeNs t1,
                   const std::function<void(TimeNs, double)>& node,
                   const std::function<void(TimeNs)>& breakpoint = {});

}  // namespace trainsim::sim
