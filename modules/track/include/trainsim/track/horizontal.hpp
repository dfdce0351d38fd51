#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "trainsim/core/enum_names.hpp"

namespace trainsim::track {

/// Shape of the curvature ramp in a transition curve.
enum class TransitionShape {
  kClothoid,  ///< curvature linear in s (Euler spiral): constant lateral jerk at constant speed
  kBloss,     ///< κ0 + Δκ (3t² − 2t³), t = s/L: curvature rate zero at both ends
};
inline constexpr EnumName<TransitionShape> kTransitionShapeNames[] = {
    {TransitionShape::kClothoid, "clothoid"}, {TransitionShape::kBloss, "bloss"}};
constexpr std::span<const EnumName<TransitionShape>> enumNames(TransitionShape) {
  return kTransitionShapeNames;
}

/// One element of a horizontal alignment, defined by its curvature law κ(s) on [0, length].
/// Curvature is signed: positive turns left (counter-clockwise seen from above, in ENU).
struct HorizontalElement {
  enum class Type { kStraight, kArc, kTransition };

  Type type = Type::kStraight;
  double length_m = 0.0;
  double curvature_start_1_m = 0.0;
  double curvature_end_1_m = 0.0;
  TransitionShape shape = TransitionShape::kClothoid;

  static HorizontalElement straight(double length_m);
  /// A circular arc of signed radius (positive: left-hand curve).
  static HorizontalElement arc(double length_m, double signed_radius_m);
  /// A transition from curvature k0 to k1 (1/m, signed).
  static HorizontalElement transition(double length_m, double k0_1_m, double k1_1_m,
                                      TransitionShape shape = TransitionShape::kClothoid);

  /// κ(s), 1/m, for 0 <= s <= length.
  double curvature(double s) const;
  /// dκ/ds, 1/m².
  double curvatureRate(double s) const;
  /// θ(s) − θ(0) = ∫₀ˢ κ du in closed form, rad.
  double headingChange(double s) const;
};

/// Position, heading and curvature of an alignment at one chainage.
struct HorizontalState {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< (east, north) in the world frame
  double heading_rad = 0.0;          ///< direction of travel, from east counter-clockwise
  double curvature_1_m = 0.0;        ///< signed, positive left
  double curvature_rate_1_m2 = 0.0;  ///< dκ/ds
};

/// A horizontal alignment: a chain of elements laid end to end from a start point and
/// heading. Heading is exact (closed form); position inside an element comes from closed forms
/// for straights and arcs and from adaptive Gauss–Legendre quadrature of (cos θ, sin θ) for
/// transitions, with an absolute error below `tolerance_m` per element. Element start points
/// are summed with compensated (Neumaier) summation, so a 1000 km chain keeps sub-millimetre
/// accuracy. Position and heading are continuous at element joints by construction; curvature
/// is continuous where the elements' end curvatures match.
class HorizontalAlignment {
 public:
  /// Throws ConfigError if an element has a non-positive or non-finite length.
  HorizontalAlignment(Eigen::Vector2d start_m, double start_heading_rad,
                      std::vector<HorizontalElement> elements, double tolerance_m = 1e-9);

  double length() const { return s_start_.back(); }
  const std::vector<HorizontalElement>& elements() const { return elements_; }
  /// Chainage where element i starts (i == elements().size() gives length()).
  double elementStart(std::size_t i) const { return s_start_[i]; }
  /// Index of the element containing chainage s (the later one at a joint).
  std::size_t elementAt(double s) const;
  /// Heading at chainage s in closed form (no position), clamped like at().
  double headingAt(double s) const;
  /// Curvature at chainage s (the later element's at a joint), clamped like at().
  double curvatureAt(double s) const;

  /// State at chainage s; s is clamped to [0, length()]. Thread-safe. Without
  /// `with_position` the position (quadrature in transitions) is left at zero: what a track
  /// laid on the Earth needs, which places itself (EarthPlacement).
  HorizontalState at(double s, bool with_position = true) const;

 private:
  Eigen::Vector2d offset(const HorizontalElement& e, double heading0, double s) const;

  std::vector<HorizontalElement> elements_;
  std::vector<double> s_start_;
  std::vector<Eigen::Vector2d> p_start_;
  std::vector<double> heading_start_;
  double tolerance_m_;
};

}  // namespace trainsim::track
