// Geodetic anchor: exact round trips far from the anchor, agreement with closed-form WGS-84
// formulas written here, and the ENU/NED conventions.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "trainsim/core/error.hpp"
#include "trainsim/core/geodesy.hpp"

namespace trainsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// WGS-84 geodetic -> ECEF, the textbook closed form (independent of GeographicLib).
Eigen::Vector3d ecef(const GeodeticPoint& p) {
  constexpr double a = 6378137.0;
  constexpr double f = 1.0 / 298.257223563;
  const double e2 = f * (2 - f);
  const double lat = p.latitude_deg * kDeg, lon = p.longitude_deg * kDeg;
  const double n = a / std::sqrt(1 - e2 * std::sin(lat) * std::sin(lat));
  return {(n + p.height_m) * std::cos(lat) * std::cos(lon),
          (n + p.height_m) * std::cos(lat) * std::sin(lon),
          (n * (1 - e2) + p.height_m) * std::sin(lat)};
}

// ECEF -> ENU at `o`, the textbook rotation.
Eigen::Vector3d enuReference(const GeodeticPoint& o, const GeodeticPoint& p) {
  const double lat = o.latitude_deg * kDeg, lon = o.longitude_deg * kDeg;
  Eigen::Matrix3d r;
  r << -std::sin(lon), std::cos(lon), 0,                                              //
      -std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat),  //
      std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat);
  return r * (ecef(p) - ecef(o));
}

const GeodeticPoint kPisa{43.7228, 10.3966, 50.0};

TEST(Frames, NedAndEnuSwapHorizontalAxesAndFlipVertical) {
  const Eigen::Vector3d enu(1.0, 2.0, 3.0);
  EXPECT_EQ(enuToNed(enu), Eigen::Vector3d(2.0, 1.0, -3.0));
  EXPECT_EQ(nedToEnu(enuToNed(enu)), enu);
  EXPECT_TRUE((rotationNedFromEnu() * enu).isApprox(enuToNed(enu)));
  EXPECT_DOUBLE_EQ(rotationNedFromEnu().determinant(), 1.0);  // both frames right-handed
}

TEST(GeodeticAnchor, AxesPointEastNorthUp) {
  const GeodeticAnchor anchor(kPisa);
  const Eigen::Vector3d north = anchor.toEnu({kPisa.latitude_deg + 1e-4, kPisa.longitude_deg, 50});
  const Eigen::Vector3d east = anchor.toEnu({kPisa.latitude_deg, kPisa.longitude_deg + 1e-4, 50});
  const Eigen::Vector3d up = anchor.toEnu({kPisa.latitude_deg, kPisa.longitude_deg, 60});
  EXPECT_GT(north.y(), 11.0);
  EXPECT_NEAR(north.x(), 0.0, 1e-6);
  EXPECT_GT(east.x(), 8.0);
  EXPECT_NEAR(east.y(), 0.0, 1e-3);
  EXPECT_NEAR(up.z(), 10.0, 1e-9);
  EXPECT_GT(anchor.toNed({kPisa.latitude_deg + 1e-4, kPisa.longitude_deg, 50}).x(), 11.0);
  EXPECT_NEAR(anchor.toNed({kPisa.latitude_deg, kPisa.longitude_deg, 60}).z(), -10.0, 1e-9);
}

TEST(GeodeticAnchor, RoundTripsStayBelowOneMillimetreAt1000km) {
  for (const GeodeticPoint origin : {kPisa, GeodeticPoint{0, 0, 0}, GeodeticPoint{-33.9, 151.2, 30},
                                     GeodeticPoint{69.6, 18.9, 10}}) {
    const GeodeticAnchor anchor(origin);
    for (int k = 0; k < 16; ++k) {
      const double bearing = k * std::numbers::pi / 8;
      const Eigen::Vector3d p_enu(1.0e6 * std::cos(bearing), 1.0e6 * std::sin(bearing),
                                  -50.0 + 100.0 * k);
      const GeodeticPoint g = anchor.fromEnu(p_enu);
      EXPECT_LT((anchor.toEnu(g) - p_enu).norm(), 1e-3);
      const Eigen::Vector3d p_ned = enuToNed(p_enu);
      EXPECT_LT((anchor.toNed(anchor.fromNed(p_ned)) - p_ned).norm(), 1e-3);
      // And starting from geodetic coordinates: compare in metres through the reference ECEF.
      const GeodeticPoint back = anchor.fromEnu(anchor.toEnu(g));
      EXPECT_LT((ecef(back) - ecef(g)).norm(), 1e-3);
    }
  }
}

TEST(GeodeticAnchor, AgreesWithClosedFormWgs84At1000km) {
  const GeodeticAnchor anchor(kPisa);
  for (const GeodeticPoint p : {GeodeticPoint{52.5, 13.4, 100}, GeodeticPoint{37.9, 23.7, 0},
                                GeodeticPoint{43.7, 24.0, 500}, GeodeticPoint{43.72, 10.40, 55}}) {
    EXPECT_LT((anchor.toEnu(p) - enuReference(kPisa, p)).norm(), 1e-3)
        << p.latitude_deg << ", " << p.longitude_deg;
  }
}

TEST(GeodeticAnchor, LocalUpTurnsWithDistanceFromAnchor) {
  const GeodeticAnchor anchor(kPisa);
  EXPECT_TRUE(anchor.rotationAnchorFromLocalEnu(Eigen::Vector3d::Zero())
                  .isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  const Eigen::Vector3d p(3.0e5, -2.0e5, 0.0);
  const GeodeticPoint g = anchor.fromEnu(p);
  const Eigen::Vector3d up =
      anchor.toEnu({g.latitude_deg, g.longitude_deg, g.height_m + 1.0}) - anchor.toEnu(g);
  const Eigen::Matrix3d r = anchor.rotationAnchorFromLocalEnu(p);
  EXPECT_LT((r * Eigen::Vector3d::UnitZ() - up).norm(), 1e-9);
  EXPECT_TRUE((r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(GeodeticAnchor, RejectsImpossibleOrigins) {
  EXPECT_THROW(GeodeticAnchor({91.0, 0.0, 0.0}), ConfigError);
  EXPECT_THROW(GeodeticAnchor({0.0, 181.0, 0.0}), ConfigError);
}

}  // namespace
}  // namespace trainsim
