#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/track/motion.hpp"
#include "trainsim/track/track.hpp"

namespace trainsim::track {

/// The carbody as a rigid body on two bogie pivots that run on the track centreline at top of
/// rail, `bogie_spacing_m` apart along the track. Body frame: origin midway between the pivots,
/// x along the chord from rear to front pivot, y to the left, z up; roll is the mean of the
/// track roll under the four wheelsets, `wheelbase_m` apart about each pivot (each bogie
/// frame rolls with the mean of its two wheelsets; no suspension). A linear cant ramp steps the
/// roll rate of a single wheelset; the mean ramps it over wheelbase / speed, so the body's
/// rate stays continuous and no point of it steps in velocity. With wheelbase 0 the roll is
/// the mean at the two pivots.
struct VehicleGeometry {
  double bogie_spacing_m = 17.5;
  double wheelbase_m = 2.5;  ///< passenger bogies: 2.5–2.7 m (docs/REFERENCES.md R1.7)
};

/// Kinematics of the body at one instant, everything in closed form from the track and the
/// motion's (u, v, a): no finite differences.
struct BodyState {
  Eigen::Vector3d front = Eigen::Vector3d::Zero();  ///< front pivot, world
  Eigen::Vector3d rear = Eigen::Vector3d::Zero();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();    ///< body origin, world
  Eigen::Vector3d origin_v = Eigen::Vector3d::Zero();  ///< its velocity, world
  Eigen::Vector3d origin_a = Eigen::Vector3d::Zero();  ///< its acceleration, world
  Eigen::Matrix3d r_world_body = Eigen::Matrix3d::Identity();
  double yaw_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;  ///< R = Rz(ψ) Ry(−θ) Rx(φ)
  Eigen::Vector3d euler_rate = Eigen::Vector3d::Zero();   ///< (φ̇, θ̇, ψ̇)
  Eigen::Vector3d w_body = Eigen::Vector3d::Zero();       ///< angular velocity, body axes
  Eigen::Vector3d alpha_body = Eigen::Vector3d::Zero();   ///< angular acceleration, body axes
  TrackPoint front_track;                                 ///< track under the front pivot

  /// Position, velocity and acceleration (world) of the body-fixed point r (body axes).
  Eigen::Vector3d pointPosition(const Eigen::Vector3d& r_body) const;
  Eigen::Vector3d pointVelocity(const Eigen::Vector3d& r_body) const;
  Eigen::Vector3d pointAcceleration(const Eigen::Vector3d& r_body) const;
};

/// Body state with the front pivot at distance `motion.u_m` along the track.
BodyState bodyState(const Track& track, const VehicleGeometry& geometry, const MotionState& motion);

}  // namespace trainsim::track
