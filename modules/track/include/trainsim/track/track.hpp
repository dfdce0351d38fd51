#pragma once

#include <vector>

#include <Eigen/Core>

#include <memory>

#include "trainsim/track/earth.hpp"
#include "trainsim/track/horizontal.hpp"
#include "trainsim/track/profile.hpp"

namespace trainsim::track {

/// Distance between rail-head centres on standard gauge, used in every cant formula.
inline constexpr double kCantBase_m = 1.5;

/// Axis about which the cant is applied. Rotating about the low (inner) rail lifts the
/// centreline by |D|/2; rotating about the centreline keeps it at the profile height. (The
/// inner-rail case also moves the centreline inward by (b/2)(1 − cos φ), about 5.4 mm at
/// 180 mm cant; that shift is neglected.) With linear ramps the inner-rail lift has a kink at
/// each end of the ramp, so the vertical velocity steps there (by v ΔD'/2); Bloss ramps are
/// smooth. Rotation about the centre is the default.
enum class CantRotation { kInnerRail, kCentre };
inline constexpr EnumName<CantRotation> kCantRotationNames[] = {
    {CantRotation::kCentre, "centre"}, {CantRotation::kInnerRail, "inner_rail"}};
constexpr std::span<const EnumName<CantRotation>> enumNames(CantRotation) {
  return kCantRotationNames;
}

/// The track centreline at top of rail and its derivatives with respect to u, the distance
/// along the track in 3D (the train's odometer distance).
struct TrackPoint {
  double chainage_m = 0.0;                             ///< s, horizontal chainage
  double distance_m = 0.0;                             ///< u
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world ENU, m
  Eigen::Vector3d d1 = Eigen::Vector3d::UnitX();       ///< dP/du
  Eigen::Vector3d d2 = Eigen::Vector3d::Zero();        ///< d²P/du², 1/m
  double heading_rad = 0.0;  ///< ψ, from the local east counter-clockwise
  double pitch_rad = 0.0;    ///< θ of the vertical profile
  double roll_rad = 0.0;     ///< φ = asin(D/b), positive with the left rail higher
  double roll_d1 = 0.0;      ///< dφ/du, rad/m
  double roll_d2 = 0.0;      ///< d²φ/du², rad/m²
  Eigen::Vector3d left = Eigen::Vector3d::UnitY();  ///< horizontal (local level), world axes
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();    ///< local vertical, world axes
  Eigen::Vector3d up_d1 = Eigen::Vector3d::Zero();  ///< d(up)/du: the ground's turn, 1/m
  Eigen::Vector3d up_d2 = Eigen::Vector3d::Zero();  ///< d²(up)/du² (to O(1/R²)), 1/m²
  double curvature_1_m = 0.0;                       ///< horizontal curvature, signed positive left
  double curvature_rate_1_m2 = 0.0;                 ///< dκ/ds
  double vertical_curvature_1_m = 0.0;              ///< dθ/du
  double cant_m = 0.0;
};

/// A track in 3D: horizontal alignment, vertical profile and cant over the same chainage.
/// Unplaced, it lies on the plane z = profile height (tests, and the design's own geometry);
/// placed on the Earth (placeOnEarth, what every planned route does), it follows the WGS-84
/// ellipsoid (EarthPlacement): chainage is ground distance, z the profile height above the
/// anchor's ellipsoidal height, grades and cant against the local level, and positions and
/// vectors in the anchor's Earth-fixed ENU frame.
class Track {
 public:
  Track(HorizontalAlignment horizontal, VerticalProfile vertical, CantProfile cant,
        CantRotation rotation = CantRotation::kCentre);

  const HorizontalAlignment& horizontal() const { return horizontal_; }
  const VerticalProfile& vertical() const { return vertical_; }
  const CantProfile& cant() const { return cant_; }
  /// Lays the track on the WGS-84 ellipsoid about `anchor` (see the class comment).
  void placeOnEarth(const GeodeticPoint& anchor);
  const EarthPlacement* earth() const { return earth_.get(); }
  CantRotation cantRotation() const { return rotation_; }

  /// Horizontal length (chainage of the end).
  double length() const { return horizontal_.length(); }
  /// Length along the track in 3D.
  double distanceLength() const { return vertical_.at(length()).distance_m; }

  TrackPoint atChainage(double s) const;
  /// Distances u (sorted, unique) where an element of the alignment, the vertical profile or
  /// the cant profile starts: where a derivative of the track may jump, so quadrature over
  /// the train's motion splits there.
  std::vector<double> breakpointDistances() const;
  TrackPoint atDistance(double u) const { return atChainage(vertical_.chainageAt(u)); }

  /// The cant angle φ and its derivatives dφ/du, d²φ/du² at distance u (TrackPoint's roll
  /// fields), without the alignment's position.
  struct Roll {
    double rad = 0.0, d1 = 0.0, d2 = 0.0;
  };
  Roll rollAtDistance(double u) const;

 private:
  HorizontalAlignment horizontal_;
  VerticalProfile vertical_;
  CantProfile cant_;
  CantRotation rotation_;
  std::shared_ptr<const EarthPlacement> earth_;  // immutable, shared by copies
};

}  // namespace trainsim::track
