#pragma once

#include <memory>

#include <Eigen/Core>

namespace trainsim {

/// Geodetic coordinates on the WGS-84 ellipsoid: latitude and longitude in degrees (at the API
/// boundary, as GNSS receivers and maps give them), ellipsoidal height in metres.
struct GeodeticPoint {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
};

/// WGS-84 radii of curvature at geodetic latitude φ (rad): meridian M and prime vertical N.
struct EllipsoidRadii {
  double meridian_m = 0.0;
  double prime_vertical_m = 0.0;
};
EllipsoidRadii wgs84Radii(double latitude_rad);
/// Earth-centred, Earth-fixed position (m) of a geodetic point given in radians and metres.
Eigen::Vector3d wgs84Ecef(double latitude_rad, double longitude_rad, double height_m);

/// Local tangent frames used by TrainSim.
///
/// The world frame is ENU (x east, y north, z up) at the scenario's geodetic anchor; route
/// files and the paper use NED (x north, y east, z down). Both are right-handed and share the
/// origin, so p_ned = (p_enu.y, p_enu.x, -p_enu.z); the map is its own inverse.
Eigen::Vector3d enuToNed(const Eigen::Vector3d& p_enu);
Eigen::Vector3d nedToEnu(const Eigen::Vector3d& p_ned);
/// Rotation R_ned_enu with p_ned = R_ned_enu * p_enu (a symmetric permutation with a sign flip).
Eigen::Matrix3d rotationNedFromEnu();

/// Places the scenario's local frame on Earth: exact conversions between geodetic coordinates
/// and the local ENU/NED frame tangent to the WGS-84 ellipsoid at the anchor (through
/// earth-centred earth-fixed coordinates, GeographicLib::LocalCartesian). No flat-Earth
/// approximation: round trips stay below a micrometre even 1000 km from the anchor.
class GeodeticAnchor {
 public:
  /// Throws ConfigError if latitude is outside [-90, 90] or longitude outside [-180, 180].
  explicit GeodeticAnchor(const GeodeticPoint& origin);
  ~GeodeticAnchor();
  GeodeticAnchor(const GeodeticAnchor& other);
  GeodeticAnchor& operator=(const GeodeticAnchor& other);

  const GeodeticPoint& origin() const { return origin_; }

  /// Local ENU position (m) of a geodetic point.
  Eigen::Vector3d toEnu(const GeodeticPoint& p) const;
  /// Geodetic point of a local ENU position (m).
  GeodeticPoint fromEnu(const Eigen::Vector3d& p_enu) const;
  Eigen::Vector3d toNed(const GeodeticPoint& p) const { return enuToNed(toEnu(p)); }
  GeodeticPoint fromNed(const Eigen::Vector3d& p_ned) const { return fromEnu(nedToEnu(p_ned)); }

  /// √(M N), the ellipsoid's Gaussian radius of curvature at the anchor (m).
  double gaussianRadius() const;
  /// The anchor's azimuthal equidistant projection (GeographicLib): (east, north) in metres
  /// whose length is the geodesic distance from the anchor and whose direction is the
  /// geodesic's azimuth there. Routes given in latitude/longitude are designed in it.
  Eigen::Vector2d toAzimuthalEquidistant(double latitude_deg, double longitude_deg) const;
  GeodeticPoint fromAzimuthalEquidistant(const Eigen::Vector2d& en, double height_m) const;
  /// Geodetic azimuth (rad, from north clockwise) at the projected point `en` of the
  /// direction that leaves it at `heading_rad` (from east counter-clockwise) in the projection.
  double azimuthOfProjectedDirection(const Eigen::Vector2d& en, double heading_rad) const;

  /// Rotation R_enu_local from the ENU frame tangent at the geodetic point of `p_enu` to the
  /// anchor's ENU frame (identity at the anchor). Needed because "up" turns by about 9e-3 rad
  /// per 57 km of distance from the anchor.
  Eigen::Matrix3d rotationAnchorFromLocalEnu(const Eigen::Vector3d& p_enu) const;

 private:
  struct Impl;
  GeodeticPoint origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trainsim
