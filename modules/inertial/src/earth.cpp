#include "trainsim/inertial/earth.hpp"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/NormalGravity.hpp>

#include <cmath>
#include <numbers>

namespace trainsim::inertial {

namespace {

struct Frame {
  Eigen::Vector3d origin_ecef;
  Eigen::Matrix3d r_ecef_world;  // columns: world E, N, U axes in ECEF
  double flat_gamma = 0.0;
};

Frame makeFrame(const GeodeticPoint& a) {
  Frame impl;
  std::vector<double> m(9);
  double x, y, z;
  GeographicLib::Geocentric::WGS84().Forward(a.latitude_deg, a.longitude_deg, a.height_m, x, y, z,
                                             m);
  impl.origin_ecef = {x, y, z};
  // GeographicLib's M is row-major and rotates local ENU to ECEF.
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      impl.r_ecef_world(r, c) = m[static_cast<std::size_t>(3 * r + c)];
  double gy = 0.0, gz = 0.0;
  GeographicLib::NormalGravity::WGS84().Gravity(a.latitude_deg, a.height_m, gy, gz);
  impl.flat_gamma = -gz;
  return impl;
}

}  // namespace

struct Earth::Impl : Frame {
  explicit Impl(const Frame& f) : Frame(f) {}
};

Earth::Earth(const GeodeticPoint& anchor, bool rotating)
    : impl_(std::make_unique<Impl>(makeFrame(anchor))), rotating_(rotating) {
  const double omega = GeographicLib::NormalGravity::WGS84().AngularVelocity();
  rate_ = rotating ? Eigen::Vector3d(impl_->r_ecef_world.transpose() * Eigen::Vector3d(0, 0, omega))
                   : Eigen::Vector3d::Zero();
}

Earth::~Earth() = default;
Earth::Earth(const Earth& other)
    : impl_(std::make_unique<Impl>(*other.impl_)), rate_(other.rate_), rotating_(other.rotating_) {}
Earth& Earth::operator=(const Earth& other) {
  if (this != &other) {
    impl_ = std::make_unique<Impl>(*other.impl_);
    rate_ = other.rate_;
    rotating_ = other.rotating_;
  }
  return *this;
}

Eigen::Vector3d Earth::gravity(const Eigen::Vector3d& p_world) const {
  if (!rotating_)
    return {0.0, 0.0, -impl_->flat_gamma};
  const Eigen::Vector3d x = impl_->origin_ecef + impl_->r_ecef_world * p_world;
  double gx, gy, gz;
  // U() returns the gravity (attraction + centrifugal) of the rotating normal ellipsoid.
  GeographicLib::NormalGravity::WGS84().U(x.x(), x.y(), x.z(), gx, gy, gz);
  return impl_->r_ecef_world.transpose() * Eigen::Vector3d(gx, gy, gz);
}

Eigen::Vector3d LocalGravity::at(const Eigen::Vector3d& p) {
  if (!earth_.rotating())
    return earth_.gravity(p);
  // Expansion points are the centres of a fixed grid, so the result is a pure function of p
  // (a resumed run or another thread gets the same bits).
  const Eigen::Vector3d cell = (p / radius_m_).array().round().matrix() * radius_m_;
  if (!valid_ || cell != p0_) {
    p0_ = cell;
    g0_ = earth_.gravity(p0_);
    constexpr double h = 10.0;  // m; the field's curvature makes the difference exact to 1e-12
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[c] = h;
      jacobian_.col(c) = (earth_.gravity(p0_ + d) - earth_.gravity(p0_ - d)) / (2.0 * h);
    }
    valid_ = true;
  }
  return g0_ + jacobian_ * (p - p0_);
}

ImuTruth imuTruth(const Earth& earth, const MountKinematics& m) {
  return imuTruth(earth, m, earth.gravity(m.p_world));
}

ImuTruth imuTruth(const Earth& earth, const MountKinematics& m, const Eigen::Vector3d& gravity) {
  const Eigen::Vector3d& omega = earth.rate();
  const Eigen::Vector3d f_world = m.a_world + 2.0 * omega.cross(m.v_world) - gravity;
  return {m.r_world_sensor.transpose() * f_world,
          m.w_sensor + m.r_world_sensor.transpose() * omega};
}

DipoleField::DipoleField(const GeodeticAnchor& anchor)
    : anchor_(anchor), r_ecef_world_(makeFrame(anchor.origin()).r_ecef_world) {}

Eigen::Vector3d DipoleField::at(const Eigen::Vector3d& p_world) const {
  constexpr double kB0 = 3.12e-5;
  constexpr double kPoleLat = 80.8 * std::numbers::pi / 180.0;
  constexpr double kPoleLon = -72.7 * std::numbers::pi / 180.0;
  const double re = GeographicLib::Constants::WGS84_a();
  const GeodeticPoint g = anchor_.fromEnu(p_world);
  double x, y, z;
  GeographicLib::Geocentric::WGS84().Forward(g.latitude_deg, g.longitude_deg, g.height_m, x, y, z);
  const Eigen::Vector3d r(x, y, z);
  const double rn = r.norm();
  const Eigen::Vector3d rh = r / rn;
  // The dipole moment points to the geomagnetic south pole (field lines enter in the north).
  const Eigen::Vector3d pole(std::cos(kPoleLat) * std::cos(kPoleLon),
                             std::cos(kPoleLat) * std::sin(kPoleLon), std::sin(kPoleLat));
  const Eigen::Vector3d mh = -pole;
  const double scale = kB0 * std::pow(re / rn, 3);
  const Eigen::Vector3d b_ecef = scale * (3.0 * mh.dot(rh) * rh - mh);
  return r_ecef_world_.transpose() * b_ecef;
}

}  // namespace trainsim::inertial
