#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/track/horizontal.hpp"
#include "trainsim/track/profile.hpp"

namespace trainsim::track {

/// Where a track lies on the WGS-84 ellipsoid. A railway's chainage is measured on the ground
/// and its heights and grades against the local level, so the alignment is not drawn on the
/// anchor's tangent plane but advanced along the Earth: at chainage s the track runs at
/// ellipsoidal height h(s) = h_anchor + z(s) (the vertical profile) with geodetic azimuth α(s),
/// and
///   dφ/ds = cos α / (M + h),  dλ/ds = sin α / ((N + h) cos φ),
///   dα/ds = −κ(s) + sin α tan φ / (N + h),
/// where κ is the design curvature (positive left) and M, N the ellipsoid's radii of
/// curvature. So s is the horizontal distance at the rail's height (what a tape on the ground
/// measures), a straight (κ = 0) is a geodesic, a curve of radius R turns by s/R against it,
/// and a level profile keeps its ellipsoidal height exactly. World positions are then
/// expressed in the anchor's Earth-fixed ENU frame (GeodeticAnchor).
///
/// The azimuth is carried as the design heading's closed form plus the slowly varying
/// geodesic term, integrated by RK4 from knots at every element start and every
/// `knot_spacing_m` (steps of at most 5 m and 0.03 rad of design heading); between knots a
/// point is integrated from the knot before it, so at(s) is a pure function of s. Positions
/// agree with an independent geodesic (GeographicLib) to well under a millimetre over
/// 100 km (tests/unit/track_earth_test.cpp).
///
/// Only every kKnotsPerChunk-th knot is kept (32 bytes per ~1.3 km); the knots of a chunk are
/// integrated again from it when a query needs them, into a small per-thread cache. They are
/// the same numbers bit for bit whenever and on whichever thread they are made, so memory
/// stays flat with the route's length and results do not depend on the order of queries.
class EarthPlacement {
 public:
  /// Lays out `horizontal` and `vertical` (z relative to the anchor's height) from the
  /// geodetic point of the design start (its design position mapped by the anchor's
  /// azimuthal equidistant projection) with the design start heading.
  EarthPlacement(const HorizontalAlignment& horizontal, const VerticalProfile& vertical,
                 const GeodeticPoint& anchor, double knot_spacing_m = 20.0);

  /// The track's place and local frame at chainage s, everything in world axes.
  struct Point {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d east = Eigen::Vector3d::UnitX(), north = Eigen::Vector3d::UnitY(),
                    up = Eigen::Vector3d::UnitZ();  ///< local ENU axes at the point
    double azimuth_rad = 0.0;                       ///< from north, clockwise
    double latitude_rad = 0.0, longitude_rad = 0.0, height_m = 0.0;
    double normal_curvature_1_m = 0.0;                ///< of the level surface along the track
    Eigen::Vector3d up_d1 = Eigen::Vector3d::Zero();  ///< d(up)/ds
    Eigen::Vector3d up_d2 = Eigen::Vector3d::Zero();  ///< d²(up)/ds² (its O(1/R²) part left out)
    /// Unit vectors along the track (horizontal) and to its left (horizontal).
    Eigen::Vector3d along() const;
    Eigen::Vector3d left() const;
  };
  Point at(const HorizontalAlignment& horizontal, const VerticalProfile& vertical, double s) const;

  const GeodeticPoint& anchor() const { return anchor_; }

 private:
  struct State {
    double s, lat, lon, delta;  // delta: azimuth minus the design heading's azimuth
  };
  // A kept knot: its state, and where it is in the knot sequence (knot k of element i's
  // subdivision, k = 0 only for the very first knot).
  struct Anchor {
    State state;
    std::uint32_t element, k;
  };
  static constexpr std::size_t kKnotsPerChunk = 64;
  // The knots of chunk c: anchor c and the kKnotsPerChunk knots after it (fewer at the end).
  const std::vector<State>& chunk(const HorizontalAlignment& horizontal,
                                  const VerticalProfile& vertical, std::size_t c) const;
  // How many knot intervals element i is cut into (at most knot_spacing_m long).
  int subdivisions(const HorizontalAlignment& horizontal, std::size_t i) const;
  // The knot after (element, k), advanced from `y`; updates element and k.
  State nextKnot(const HorizontalAlignment& horizontal, const VerticalProfile& vertical,
                 const State& y, std::uint32_t& element, std::uint32_t& k) const;
  // Integrates from `from` to s in the number of steps that the knot interval [from.s, to]
  // takes.
  State advance(const HorizontalAlignment& horizontal, const VerticalProfile& vertical, State from,
                double s, double to) const;
  double designAzimuth(const HorizontalAlignment& horizontal, double s) const;

  GeodeticPoint anchor_;
  double azimuth0_ = 0.0;  // azimuth at s = 0
  double heading0_ = 0.0;  // design heading at s = 0
  Eigen::Vector3d ecef0_;
  Eigen::Matrix3d r_world_ecef_;
  double knot_spacing_m_ = 20.0;
  std::size_t knot_count_ = 0;
  std::vector<Anchor> anchors_;
  std::uint64_t id_ = 0;  // names this placement's knots in the per-thread cache
};

}  // namespace trainsim::track
