#include "trainsim/track/horizontal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "trainsim/core/error.hpp"

namespace trainsim::track {

HorizontalElement HorizontalElement::straight(double length_m) {
  return {Type::kStraight, length_m, 0.0, 0.0, TransitionShape::kClothoid};
}

HorizontalElement HorizontalElement::arc(double length_m, double signed_radius_m) {
  const double k = 1.0 / signed_radius_m;
  return {Type::kArc, length_m, k, k, TransitionShape::kClothoid};
}

HorizontalElement HorizontalElement::transition(double length_m, double k0, double k1,
                                                TransitionShape shape) {
  return {Type::kTransition, length_m, k0, k1, shape};
}

double HorizontalElement::curvature(double s) const {
  if (type != Type::kTransition)
    return curvature_start_1_m;
  const double t = s / length_m;
  const double dk = curvature_end_1_m - curvature_start_1_m;
  return shape == TransitionShape::kClothoid ? curvature_start_1_m + dk * t
                                             : curvature_start_1_m + dk * t * t * (3.0 - 2.0 * t);
}

double HorizontalElement::curvatureRate(double s) const {
  if (type != Type::kTransition)
    return 0.0;
  const double t = s / length_m;
  const double dk = curvature_end_1_m - curvature_start_1_m;
  return shape == TransitionShape::kClothoid ? dk / length_m : dk * 6.0 * t * (1.0 - t) / length_m;
}

double HorizontalElement::headingChange(double s) const {
  if (type != Type::kTransition)
    return curvature_start_1_m * s;
  const double t = s / length_m;
  const double dk = curvature_end_1_m - curvature_start_1_m;
  // ∫ κ: clothoid Δκ s²/(2L); Bloss Δκ L (t³ − t⁴/2).
  return shape == TransitionShape::kClothoid
             ? curvature_start_1_m * s + dk * s * t / 2.0
             : curvature_start_1_m * s + dk * length_m * t * t * t * (1.0 - t / 2.0);
}

namespace {

// sin(x)/x, accurate near 0.
double sinc(double x) {
  if (std::abs(x) < 1e-4)
    return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

// 7-point Gauss–Legendre rule on [-1, 1] (exact for polynomials of degree 13). Hand-written
// because none of the project's dependencies (docs/REFERENCES.md P5) offers quadrature; Eigen
// has none.
constexpr std::array<double, 7> kNodes = {0.0,
                                          0.4058451513773971669066064,
                                          -0.4058451513773971669066064,
                                          0.7415311855993944398638648,
                                          -0.7415311855993944398638648,
                                          0.9491079123427585245261897,
                                          -0.9491079123427585245261897};
constexpr std::array<double, 7> kWeights = {
    0.4179591836734693877551020, 0.3818300505051189449503698, 0.3818300505051189449503698,
    0.2797053914892766679014678, 0.2797053914892766679014678, 0.1294849661688696932706114,
    0.1294849661688696932706114};

template <typename Heading>
Eigen::Vector2d gaussLegendre(const Heading& heading, double a, double b) {
  const double half = 0.5 * (b - a);
  const double mid = 0.5 * (a + b);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < kNodes.size(); ++i) {
    const double th = heading(mid + half * kNodes[i]);
    sum += kWeights[i] * Eigen::Vector2d(std::cos(th), std::sin(th));
  }
  return half * sum;
}

// Adaptive bisection: accept a panel when the two-half estimate differs from the whole-panel
// estimate by less than its share of the tolerance. That difference bounds the error of the
// coarser estimate, so it over-bounds the error of the finer one that is returned. No panel
// is asked for less than its rounding floor: the heading θ carries an error of about ε·|θ|, so
// a panel of length h cannot be known better than ε·|θ|·h, whatever the tolerance; without this
// floor a panel far along a tight spiral would split 2^40 times. The depth bounds the work of a
// call to 2^24 panels whatever the input.
constexpr int kMaxDepth = 24;

template <typename Heading>
Eigen::Vector2d adaptive(const Heading& heading, double a, double b, const Eigen::Vector2d& whole,
                         double tolerance, int depth) {
  const double m = 0.5 * (a + b);
  const Eigen::Vector2d left = gaussLegendre(heading, a, m);
  const Eigen::Vector2d right = gaussLegendre(heading, m, b);
  const Eigen::Vector2d both = left + right;
  const double floor =
      64.0 * std::numeric_limits<double>::epsilon() * (1.0 + std::abs(heading(m))) * (b - a);
  if ((both - whole).norm() <= std::max(tolerance, floor) || depth >= kMaxDepth)
    return both;
  return adaptive(heading, a, m, left, tolerance / 2, depth + 1) +
         adaptive(heading, m, b, right, tolerance / 2, depth + 1);
}

}  // namespace

Eigen::Vector2d HorizontalAlignment::offset(const HorizontalElement& e, double heading0,
                                            double s) const {
  if (s <= 0.0)
    return Eigen::Vector2d::Zero();
  if (e.type != HorizontalElement::Type::kTransition) {
    // Chord of an arc (or straight): length s·sinc(κs/2) along the mean heading θ0 + κs/2.
    const double half_turn = 0.5 * e.curvature_start_1_m * s;
    const double chord = s * sinc(half_turn);
    return chord * Eigen::Vector2d(std::cos(heading0 + half_turn), std::sin(heading0 + half_turn));
  }
  const auto heading = [&](double u) { return heading0 + e.headingChange(u); };
  return adaptive(heading, 0.0, s, gaussLegendre(heading, 0.0, s), tolerance_m_, 0);
}

HorizontalAlignment::HorizontalAlignment(Eigen::Vector2d start_m, double start_heading_rad,
                                         std::vector<HorizontalElement> elements,
                                         double tolerance_m)
    : elements_(std::move(elements)), tolerance_m_(tolerance_m) {
  if (elements_.empty()) {
    throw ConfigError("alignment has no elements");
  }
  if (!(tolerance_m_ > 0.0)) {
    throw ConfigError("alignment quadrature tolerance must be positive");
  }
  s_start_.reserve(elements_.size() + 1);
  // Neumaier-compensated running sums keep the joints exact to about 1 ulp of the total, even
  // after thousands of elements and 1000 km.
  double s = 0.0, s_c = 0.0, th = start_heading_rad;
  Eigen::Vector2d p = start_m, p_c = Eigen::Vector2d::Zero();
  auto add = [](double& sum, double& c, double x) {
    const double t = sum + x;
    c += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  };
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const HorizontalElement& e = elements_[i];
    if (!(e.length_m > 0.0) || !std::isfinite(e.length_m)) {
      throw ConfigError(
          fmt::format("alignment element {}: length {} m is not positive", i, e.length_m));
    }
    s_start_.push_back(s + s_c);
    p_start_.push_back(p + p_c);
    heading_start_.push_back(th);
    const Eigen::Vector2d d = offset(e, th, e.length_m);
    add(p.x(), p_c.x(), d.x());
    add(p.y(), p_c.y(), d.y());
    add(s, s_c, e.length_m);
    th += e.headingChange(e.length_m);
  }
  s_start_.push_back(s + s_c);
}

std::size_t HorizontalAlignment::elementAt(double s) const {
  const auto it = std::upper_bound(s_start_.begin(), s_start_.end() - 1, s);
  return it == s_start_.begin() ? 0 : static_cast<std::size_t>(it - s_start_.begin()) - 1;
}

double HorizontalAlignment::headingAt(double s) const {
  s = std::clamp(s, 0.0, length());
  const std::size_t i = elementAt(s);
  return heading_start_[i] + elements_[i].headingChange(s - s_start_[i]);
}

double HorizontalAlignment::curvatureAt(double s) const {
  s = std::clamp(s, 0.0, length());
  const std::size_t i = elementAt(s);
  return elements_[i].curvature(s - s_start_[i]);
}

HorizontalState HorizontalAlignment::at(double s, bool with_position) const {
  s = std::clamp(s, 0.0, length());
  const std::size_t i = elementAt(s);
  const HorizontalElement& e = elements_[i];
  const double local = std::min(s - s_start_[i], e.length_m);
  HorizontalState st;
  st.heading_rad = heading_start_[i] + e.headingChange(local);
  if (with_position)
    st.position_m = p_start_[i] + offset(e, heading_start_[i], local);
  st.curvature_1_m = e.curvature(local);
  st.curvature_rate_1_m2 = e.curvatureRate(local);
  return st;
}

}  // namespace trainsim::track
