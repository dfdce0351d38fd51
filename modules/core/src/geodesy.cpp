#include "trainsim/core/geodesy.hpp"

#include <GeographicLib/AzimuthalEquidistant.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "trainsim/core/error.hpp"

namespace trainsim {

namespace {
double wgs84E2() {
  const double f = GeographicLib::Constants::WGS84_f();
  return f * (2.0 - f);
}
}  // namespace

EllipsoidRadii wgs84Radii(double lat) {
  static const double e2 = wgs84E2();
  const double s = std::sin(lat);
  const double w2 = 1.0 - e2 * s * s;
  const double n = GeographicLib::Constants::WGS84_a() / std::sqrt(w2);
  return {n * (1.0 - e2) / w2, n};
}

Eigen::Vector3d wgs84Ecef(double lat, double lon, double h) {
  static const double e2 = wgs84E2();
  const double n = wgs84Radii(lat).prime_vertical_m;
  return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - e2) + h) * std::sin(lat)};
}

Eigen::Vector3d enuToNed(const Eigen::Vector3d& p_enu) {
  return {p_enu.y(), p_enu.x(), -p_enu.z()};
}
Eigen::Vector3d nedToEnu(const Eigen::Vector3d& p_ned) {
  return {p_ned.y(), p_ned.x(), -p_ned.z()};
}

Eigen::Matrix3d rotationNedFromEnu() {
  Eigen::Matrix3d r;
  r << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  return r;
}

struct GeodeticAnchor::Impl {
  GeographicLib::LocalCartesian local;
};

namespace {
void checkGeodetic(const GeodeticPoint& p) {
  if (!(std::abs(p.latitude_deg) <= 90.0)) {
    throw ConfigError("latitude " + std::to_string(p.latitude_deg) + " deg is outside [-90, 90]");
  }
  if (!(std::abs(p.longitude_deg) <= 180.0)) {
    throw ConfigError("longitude " + std::to_string(p.longitude_deg) +
                      " deg is outside [-180, 180]");
  }
  if (!std::isfinite(p.height_m)) {
    throw ConfigError("height is not a finite number");
  }
}
}  // namespace

GeodeticAnchor::GeodeticAnchor(const GeodeticPoint& origin)
    : origin_(origin), impl_(std::make_unique<Impl>()) {
  checkGeodetic(origin);
  impl_->local.Reset(origin.latitude_deg, origin.longitude_deg, origin.height_m);
}

GeodeticAnchor::~GeodeticAnchor() = default;
GeodeticAnchor::GeodeticAnchor(const GeodeticAnchor& other)
    : origin_(other.origin_), impl_(std::make_unique<Impl>(*other.impl_)) {}
GeodeticAnchor& GeodeticAnchor::operator=(const GeodeticAnchor& other) {
  if (this != &other) {
    origin_ = other.origin_;
    impl_ = std::make_unique<Impl>(*other.impl_);
  }
  return *this;
}

Eigen::Vector3d GeodeticAnchor::toEnu(const GeodeticPoint& p) const {
  Eigen::Vector3d enu;
  impl_->local.Forward(p.latitude_deg, p.longitude_deg, p.height_m, enu.x(), enu.y(), enu.z());
  return enu;
}

GeodeticPoint GeodeticAnchor::fromEnu(const Eigen::Vector3d& p_enu) const {
  GeodeticPoint p;
  impl_->local.Reverse(p_enu.x(), p_enu.y(), p_enu.z(), p.latitude_deg, p.longitude_deg,
                       p.height_m);
  return p;
}

double GeodeticAnchor::gaussianRadius() const {
  const EllipsoidRadii r = wgs84Radii(origin_.latitude_deg * std::numbers::pi / 180.0);
  return std::sqrt(r.meridian_m * r.prime_vertical_m);
}

Eigen::Vector2d GeodeticAnchor::toAzimuthalEquidistant(double lat, double lon) const {
  const GeographicLib::AzimuthalEquidistant aep(GeographicLib::Geodesic::WGS84());
  double x = 0, y = 0, azi = 0, rk = 0;
  aep.Forward(origin_.latitude_deg, origin_.longitude_deg, lat, lon, x, y, azi, rk);
  return {x, y};
}

GeodeticPoint GeodeticAnchor::fromAzimuthalEquidistant(const Eigen::Vector2d& en,
                                                       double height_m) const {
  const GeographicLib::AzimuthalEquidistant aep(GeographicLib::Geodesic::WGS84());
  GeodeticPoint p;
  double azi = 0, rk = 0;
  aep.Reverse(origin_.latitude_deg, origin_.longitude_deg, en.x(), en.y(), p.latitude_deg,
              p.longitude_deg, azi, rk);
  p.height_m = height_m;
  return p;
}

double GeodeticAnchor::azimuthOfProjectedDirection(const Eigen::Vector2d& en,
                                                   double heading_rad) const {
  // Through a point 1 m along the direction: the projection's distortion over 1 m is far
  // below the 1e-9 rad this is used to.
  const GeodeticPoint a = fromAzimuthalEquidistant(en, 0.0);
  const GeodeticPoint b = fromAzimuthalEquidistant(
      en + Eigen::Vector2d(std::cos(heading_rad), std::sin(heading_rad)), 0.0);
  double s12 = 0, azi1 = 0, azi2 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(a.latitude_deg, a.longitude_deg, b.latitude_deg,
                                           b.longitude_deg, s12, azi1, azi2);
  return azi1 * std::numbers::pi / 180.0;
}

Eigen::Matrix3d GeodeticAnchor::rotationAnchorFromLocalEnu(const Eigen::Vector3d& p_enu) const {
  // LocalCartesian::Reverse returns M with v_anchor_enu = M * v_local_enu, row-major.
  std::vector<double> m(9);
  double lat = 0, lon = 0, h = 0;
  impl_->local.Reverse(p_enu.x(), p_enu.y(), p_enu.z(), lat, lon, h, m);
  Eigen::Matrix3d r;
  r << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
  return r;
}

}  // namespace trainsim
