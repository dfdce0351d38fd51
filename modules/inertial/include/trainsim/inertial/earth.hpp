#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/core/geodesy.hpp"

namespace trainsim::inertial {

/// Gravity and Earth rotation in the world frame: the Earth-fixed ENU frame tangent at the
/// scenario's anchor. The gravity is WGS-84 normal gravity (GeographicLib NormalGravity: the
/// attraction plus the centrifugal term, so it must not be added again) at the point's true
/// ECEF position; the Earth rate Ω = 7.292115e-5 rad/s about the ECEF z axis, seen in world
/// axes. Because the world frame is Earth-fixed and Cartesian, the "transport rate" of a
/// local-level navigation frame is already part of the body's rate relative to it.
/// `rotating = false` gives the flat, non-rotating debug Earth: g = (0, 0, −γ(anchor)), Ω = 0.
class Earth {
 public:
  Earth(const GeodeticPoint& anchor, bool rotating = true);
  ~Earth();
  Earth(const Earth&);
  Earth& operator=(const Earth&);

  /// Normal gravity vector at world position p (m/s², world axes; points down, |g| ≈ 9.8).
  Eigen::Vector3d gravity(const Eigen::Vector3d& p_world) const;
  /// Earth rotation rate vector in world axes (rad/s).
  const Eigen::Vector3d& rate() const { return rate_; }
  bool rotating() const { return rotating_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Eigen::Vector3d rate_;
  bool rotating_;
};

/// Normal gravity along a path, from a first-order expansion g(p0) + J (p − p0) about the
/// centre p0 of the `cell_m` grid cell holding p (the Jacobian J by central differences of the
/// exact field). The result is a pure function of p; the neglected second-order term is below
/// 1e-8 m/s² for the default 50 m cells, and a train at 100 Hz pays for about one exact
/// evaluation per second instead of one per reading. Not thread-safe: one per sensor.
class LocalGravity {
 public:
  explicit LocalGravity(const Earth& earth, double cell_m = 50.0)
      : earth_(earth), radius_m_(cell_m) {}
  Eigen::Vector3d at(const Eigen::Vector3d& p_world);

 private:
  const Earth& earth_;
  double radius_m_;
  bool valid_ = false;
  Eigen::Vector3d p0_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d g0_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d jacobian_ = Eigen::Matrix3d::Zero();
};

/// What a body-fixed sensor experiences relative to the Earth-fixed world frame.
struct MountKinematics {
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();  ///< relative to the Earth
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();  ///< d²p/dt² in the Earth-fixed frame
  Eigen::Matrix3d r_world_sensor = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_sensor = Eigen::Vector3d::Zero();  ///< rate relative to the Earth, sensor axes
};

/// True specific force and inertial angular rate, in sensor axes.
struct ImuTruth {
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();  ///< m/s²
  Eigen::Vector3d angular_rate = Eigen::Vector3d::Zero();    ///< rad/s, ω_is
};

/// f = Rᵀ (a + 2 Ω × v − g(p)) and ω_is = ω_es + Rᵀ Ω (the centrifugal term is inside g).
ImuTruth imuTruth(const Earth& earth, const MountKinematics& m);
/// The same with the gravity vector at m.p_world given (e.g. from LocalGravity).
ImuTruth imuTruth(const Earth& earth, const MountKinematics& m, const Eigen::Vector3d& gravity);

/// Earth's main field as a tilted centred dipole (geomagnetic north pole at 80.8° N, 72.7° W,
/// B0 = 3.12e-5 T at the equator), in tesla, world axes. A stand-in for WMM, accurate to some
/// degrees in declination; it gives the magnetometer a physically shaped reference.
class DipoleField {
 public:
  explicit DipoleField(const GeodeticAnchor& anchor);
  Eigen::Vector3d at(const Eigen::Vector3d& p_world) const;

 private:
  GeodeticAnchor anchor_;
  Eigen::Matrix3d r_ecef_world_;  // the anchor's ENU axes in ECEF, computed once
};

}  // namespace trainsim::inertial
