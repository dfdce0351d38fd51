#include "trainsim/track/track.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "trainsim/core/error.hpp"

namespace trainsim::track {

Track::Track(HorizontalAlignment horizontal, VerticalProfile vertical, CantProfile cant,
             CantRotation rotation)
    : horizontal_(std::move(horizontal)),
      vertical_(std::move(vertical)),
      cant_(std::move(cant)),
      rotation_(rotation) {
  if (vertical_.length() + 1e-6 < horizontal_.length())
    throw ConfigError(fmt::format("vertical profile ({} m) is shorter than the alignment ({} m)",
                                  vertical_.length(), horizontal_.length()));
}

void Track::placeOnEarth(const GeodeticPoint& anchor) {
  earth_ = std::make_shared<const EarthPlacement>(horizontal_, vertical_, anchor);
}

std::vector<double> Track::breakpointDistances() const {
  std::vector<double> s;
  for (std::size_t i = 0; i <= horizontal_.elements().size(); ++i)
    s.push_back(horizontal_.elementStart(i));
  for (std::size_t i = 0; i <= vertical_.elements().size(); ++i)
    s.push_back(vertical_.elementStart(i));
  for (std::size_t i = 0; !cant_.elements().empty() && i <= cant_.elements().size(); ++i)
    s.push_back(cant_.elementStart(i));
  std::vector<double> u;
  for (double c : s)
    if (c >= 0.0 && c <= length())
      u.push_back(vertical_.at(c).distance_m);
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  return u;
}

namespace {

// φ = asin(D / b) and its derivatives along u, from the cant's along s (s_u = ds/du, s_uu).
Track::Roll rollOf(const CantState& d, double s, double s_u, double s_uu) {
  const double b2 = kCantBase_m * kCantBase_m - d.cant_m * d.cant_m;
  if (b2 <= 0.0)
    throw RuntimeError(
        fmt::format("cant {} m at chainage {} m exceeds the rail base", d.cant_m, s));
  const double g = 1.0 / std::sqrt(b2);     // dφ/dD
  const double g_d = d.cant_m * g * g * g;  // d²φ/dD²
  const double d_u = d.rate_m_per_m * s_u;
  const double d_uu = d.rate2_1_m * s_u * s_u + d.rate_m_per_m * s_uu;
  return {std::asin(d.cant_m / kCantBase_m), g * d_u, g_d * d_u * d_u + g * d_uu};
}

}  // namespace

Track::Roll Track::rollAtDistance(double u) const {
  const double s = vertical_.chainageAt(u);
  const VerticalState v = vertical_.at(s);
  return rollOf(cant_.at(s), s, std::cos(v.pitch_rad), -std::sin(v.pitch_rad) * v.curvature_1_m);
}

TrackPoint Track::atChainage(double s) const {
  const HorizontalState h = horizontal_.at(s, /*with_position=*/!earth_);
  const VerticalState v = vertical_.at(s);
  const CantState d = cant_.at(s);
  TrackPoint p;
  p.chainage_m = s;
  p.distance_m = v.distance_m;
  p.heading_rad = h.heading_rad;  // the plane's; on the Earth, the local heading below
  p.pitch_rad = v.pitch_rad;
  p.curvature_1_m = h.curvature_1_m;
  p.curvature_rate_1_m2 = h.curvature_rate_1_m2;
  p.vertical_curvature_1_m = v.curvature_1_m;
  p.cant_m = d.cant_m;

  const double c = std::cos(v.pitch_rad);
  const double sp = std::sin(v.pitch_rad);
  const double k = v.curvature_1_m;
  const double kappa = h.curvature_1_m;
  // ds/du = cos θ, d²s/du² = −sin θ k.
  const double s_u = c;
  const double s_uu = -sp * k;

  // The local frame: the plane's axes, or the ground's on the Earth. t and l are horizontal.
  Eigen::Vector3d t, l, up, up_s = Eigen::Vector3d::Zero(), up_ss = Eigen::Vector3d::Zero();
  double normal_curvature = 0.0;
  if (earth_) {
    const EarthPlacement::Point g = earth_->at(horizontal_, vertical_, s);
    t = g.along();
    l = g.left();
    up = g.up;
    up_s = g.up_d1;
    up_ss = g.up_d2;
    normal_curvature = g.normal_curvature_1_m;
    p.position = g.position;
    p.heading_rad = std::atan2(std::cos(g.azimuth_rad), std::sin(g.azimuth_rad));
  } else {
    t << std::cos(h.heading_rad), std::sin(h.heading_rad), 0.0;
    l << -t.y(), t.x(), 0.0;
    up = Eigen::Vector3d::UnitZ();
    p.position << h.position_m.x(), h.position_m.y(), v.z_m;
  }

  // Centreline lift when the cant rotates about the inner rail: |D|/2 along up (its O(1/R)
  // turn with the ground is left out: below 1e-8).
  double lift = 0.0, lift_s = 0.0, lift_ss = 0.0;
  if (rotation_ == CantRotation::kInnerRail && d.cant_m != 0.0) {
    const double sign = d.cant_m > 0.0 ? 1.0 : -1.0;
    lift = 0.5 * std::abs(d.cant_m);
    lift_s = 0.5 * sign * d.rate_m_per_m;
    lift_ss = 0.5 * sign * d.rate2_1_m;
  }
  // P(s) = ground point at height h(s): dP/ds = t + h' up, d²P/ds² = κ l − k_n up + h'' up +
  // h' up', with h' = tan θ and h'' = k / cos³ θ; then along u by the chain rule.
  const double h1 = sp / c, h2 = k / (c * c * c);
  const Eigen::Vector3d p_s = t + h1 * up;
  const Eigen::Vector3d p_ss = kappa * l - normal_curvature * up + h2 * up + h1 * up_s;
  p.position += lift * up;
  p.d1 = p_s * s_u + lift_s * s_u * up;
  p.d2 = p_ss * s_u * s_u + p_s * s_uu + (lift_ss * s_u * s_u + lift_s * s_uu) * up;
  p.left = l;
  p.up = up;
  p.up_d1 = up_s * s_u;
  p.up_d2 = up_ss * s_u * s_u + up_s * s_uu;

  const Roll roll = rollOf(d, s, s_u, s_uu);
  p.roll_rad = roll.rad;
  p.roll_d1 = roll.d1;
  p.roll_d2 = roll.d2;
  return p;
}

}  // namespace trainsim::track
