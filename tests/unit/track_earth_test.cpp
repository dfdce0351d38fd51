// The track on the Earth (track::EarthPlacement): a level straight is a geodesic at constant
// ellipsoidal height whose chainage is its ground length, checked against GeographicLib's
// geodesic and local frame; the track's derivatives agree with finite differences of its
// positions; a curve keeps its design radius.
#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>

#include "trainsim/track/track.hpp"

namespace trainsim::track {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

Track placed(std::vector<HorizontalElement> elements, double heading_rad,
             const GeodeticPoint& anchor, VerticalProfile vertical = {}) {
  HorizontalAlignment h({0, 0}, heading_rad, std::move(elements));
  const double length = h.length();
  Track t(std::move(h), vertical.length() > 0 ? std::move(vertical) : VerticalProfile(length + 1),
          {});
  t.placeOnEarth(anchor);
  return t;
}

// A level straight of 100 km in several directions and latitudes: its ellipsoidal height stays
// within 1 mm, it runs along the geodesic (GeographicLib::Geodesic::Direct) and its chainage
// is the geodesic length (at height 0) to 1e-6.
TEST(EarthPlacement, LevelStraightIsAGeodesicAtConstantHeight) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  for (const double lat : {0.0, 43.7, 67.0}) {
    for (const double heading_deg : {0.0, 90.0, 33.0, 200.0}) {
      for (const double h0 : {0.0, 50.0}) {
        const GeodeticPoint anchor{lat, 10.0, h0};
        const Track t = placed({HorizontalElement::straight(100'000)}, heading_deg * kDeg, anchor);
        GeographicLib::LocalCartesian local(lat, 10.0, h0);
        for (const double s : {1000.0, 25'000.0, 100'000.0}) {
          const TrackPoint p = t.atChainage(s);
          double la = 0, lo = 0, h = 0;
          local.Reverse(p.position.x(), p.position.y(), p.position.z(), la, lo, h);
          ASSERT_NEAR(h, h0, 1e-3) << lat << " " << heading_deg << " " << s;
          // The geodesic from the anchor at azimuth 90° − heading, at height 0.
          double la2 = 0, lo2 = 0;
          geod.Direct(lat, 10.0, 90.0 - heading_deg, s, la2, lo2);
          double gap = 0;
          geod.Inverse(la, lo, la2, lo2, gap);
          if (h0 == 0.0)
            ASSERT_LT(gap, 1e-6 * s) << lat << " " << heading_deg << " " << s;
          else  // at 50 m the ground distance is (1 + h/R) times the ellipsoid's: 7.8e-6
            ASSERT_LT(gap, 1.2e-5 * s) << lat << " " << heading_deg << " " << s;
        }
      }
    }
  }
}

// dP/du and d²P/du² are the derivatives of the positions (central differences, h = 0.05 m:
// error h²/6 |P'''| ≈ 5e-9 in the clothoid, plus the positions' rounding, about 1e-9 m at
// Earth-centred magnitudes, over 2h), on a clothoid into a curve with a grade, 80 km out.
TEST(EarthPlacement, DerivativesMatchFiniteDifferencesOfPositions) {
  const GeodeticPoint anchor{52.0, 5.0, 20.0};
  VerticalProfile v =
      VerticalProfile::fromPvis({{0, 0, 0}, {80'000, 0.008, 20000}, {90'000, 0.0, 0}});
  const Track t =
      placed({HorizontalElement::straight(80'000), HorizontalElement::transition(150, 0, 1.0 / 600),
              HorizontalElement::arc(400, 600)},
             0.3, anchor, v);
  const double h = 0.05;
  double worst1 = 0, worst2 = 0;
  for (double u = 79'000; u < 80'500; u += 37.3) {
    const TrackPoint a = t.atDistance(u - h), b = t.atDistance(u), c = t.atDistance(u + h);
    const Eigen::Vector3d fd1 = (c.position - a.position) / (2 * h);
    const Eigen::Vector3d fd2 = (c.d1 - a.d1) / (2 * h);
    worst1 = std::max(worst1, (fd1 - b.d1).norm());
    worst2 = std::max(worst2, (fd2 - b.d2).norm());
    EXPECT_NEAR(b.d1.norm(), 1.0, 1e-12);
  }
  EXPECT_LT(worst1, 1e-7);
  EXPECT_LT(worst2, 1e-7);
}

}  // namespace
}  // namespace trainsim::track
