#include "trainsim/track/profile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "trainsim/core/error.hpp"

namespace trainsim::track {
namespace {

std::size_t indexIn(const std::vector<double>& starts, double x) {
  // starts has one more entry than there are elements; pick the element containing x.
  const auto it = std::upper_bound(starts.begin(), starts.end() - 1, x);
  return it == starts.begin() ? 0 : static_cast<std::size_t>(it - starts.begin()) - 1;
}

// asin(y)/y, accurate near 0.
double asinc(double y) {
  if (std::abs(y) < 1e-5)
    return 1.0 + y * y / 6.0;
  return std::asin(y) / y;
}

double sinc(double x) {
  if (std::abs(x) < 1e-5)
    return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

struct Local {
  double z;
  double sin_pitch;
  double u;
};

// Height and 3D distance gained over horizontal distance x on a vertical element, written
// without cancellation so that they stay exact as the curvature tends to zero:
//   Δz = x (σ + σ0) / (c0 + c),   Δu = asin(sin Δθ) / k with sin Δθ = k x m.
Local advance(const VerticalElement& e, double x) {
  const double s0 = e.sin_pitch_start;
  const double s1 = s0 + e.curvature_1_m * x;
  if (std::abs(s1) >= 1.0)
    throw RuntimeError(fmt::format("vertical profile reaches a vertical tangent ({} m in)", x));
  const double c0 = std::sqrt(1.0 - s0 * s0);
  const double c1 = std::sqrt(1.0 - s1 * s1);
  const double dz = x * (s1 + s0) / (c0 + c1);
  const double m = c0 + s0 * (s1 + s0) / (c0 + c1);
  const double du = x * m * asinc(e.curvature_1_m * x * m);
  return {dz, s1, du};
}

}  // namespace

VerticalProfile::VerticalProfile(double length_m, double z0_m)
    : VerticalProfile(z0_m, {VerticalElement{length_m, 0.0, 0.0}}) {}

VerticalProfile::VerticalProfile(double z0_m, std::vector<VerticalElement> elements)
    : elements_(std::move(elements)) {
  if (elements_.empty())
    elements_.push_back({0.0, 0.0, 0.0});
  s_start_ = {0.0};
  u_start_ = {0.0};
  z_start_ = {z0_m};
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const VerticalElement& e = elements_[i];
    if (!(e.length_m >= 0.0) || !std::isfinite(e.length_m))
      throw ConfigError(
          fmt::format("vertical element {}: length {} m is not valid", i, e.length_m));
    const Local l = advance(e, e.length_m);
    s_start_.push_back(s_start_.back() + e.length_m);
    u_start_.push_back(u_start_.back() + l.u);
    z_start_.push_back(z_start_.back() + l.z);
  }
}

VerticalProfile VerticalProfile::fromPvis(const std::vector<Pvi>& pvis,
                                          std::vector<std::pair<std::size_t, double>>* reduced) {
  if (pvis.size() < 2)
    throw ConfigError("a vertical profile needs at least two points");
  const std::size_t n = pvis.size();
  std::vector<double> pitch(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double ds = pvis[i + 1].chainage_m - pvis[i].chainage_m;
    if (!(ds > 0.0))
      throw ConfigError(
          fmt::format("vertical points {} and {} are not in increasing chainage", i, i + 1));
    pitch[i] = std::atan2(pvis[i + 1].z_m - pvis[i].z_m, ds);
  }
  // Tangent length along each grade line: T = R tan(|Δθ|/2); horizontally T cos θ.
  std::vector<double> radius(n, 0.0);
  std::vector<double> half(n, 0.0);  // T / R
  for (std::size_t i = 1; i + 1 < n; ++i) {
    radius[i] = std::max(0.0, pvis[i].radius_m);
    half[i] = std::tan(std::abs(pitch[i] - pitch[i - 1]) / 2.0);
  }
  std::vector<double> scale(n, 1.0);
  for (std::size_t leg = 0; leg + 1 < n; ++leg) {
    const double c = std::cos(pitch[leg]);
    const double need = (radius[leg] * half[leg] + radius[leg + 1] * half[leg + 1]) * c;
    const double room = pvis[leg + 1].chainage_m - pvis[leg].chainage_m;
    if (need > room) {
      const double f = room / need;
      scale[leg] = std::min(scale[leg], f);
      scale[leg + 1] = std::min(scale[leg + 1], f);
    }
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (scale[i] < 1.0) {
      radius[i] *= scale[i] * (1.0 - 1e-12);
      if (reduced)
        reduced->emplace_back(i, radius[i]);
    }
  }
  std::vector<VerticalElement> elements;
  double s = pvis[0].chainage_m;
  for (std::size_t leg = 0; leg + 1 < n; ++leg) {
    const double after = radius[leg + 1] * half[leg + 1];
    const double grade_end = pvis[leg + 1].chainage_m - after * std::cos(pitch[leg]);
    if (grade_end - s > 1e-9)
      elements.push_back({grade_end - s, std::sin(pitch[leg]), 0.0});
    s = std::max(s, grade_end);
    const double len =
        leg + 2 < n ? after * (std::cos(pitch[leg]) + std::cos(pitch[leg + 1])) : 0.0;
    if (len > 1e-9) {
      const double s0 = std::sin(pitch[leg]);
      const double s1 = std::sin(pitch[leg + 1]);
      elements.push_back({len, s0, (s1 - s0) / len});
      s += len;
    }
  }
  if (elements.empty())
    elements.push_back({pvis.back().chainage_m - pvis[0].chainage_m, std::sin(pitch[0]), 0.0});
  return VerticalProfile(pvis[0].z_m, std::move(elements));
}

std::size_t VerticalProfile::indexAtChainage(double s) const {
  return indexIn(s_start_, s);
}

VerticalState VerticalProfile::at(double s) const {
  const std::size_t i = indexAtChainage(s);
  const VerticalElement& e = elements_[i];
  const Local l = advance(e, s - s_start_[i]);
  return {z_start_[i] + l.z, std::asin(l.sin_pitch), e.curvature_1_m, u_start_[i] + l.u};
}

double VerticalProfile::chainageAt(double u) const {
  const std::size_t i = indexIn(u_start_, u);
  const VerticalElement& e = elements_[i];
  const double du = u - u_start_[i];
  const double theta0 = std::asin(e.sin_pitch_start);
  const double half_turn = 0.5 * e.curvature_1_m * du;
  // x = (sin θ − sin θ0)/k = Δu cos(θ0 + Δθ/2) sinc(Δθ/2).
  return s_start_[i] + du * std::cos(theta0 + half_turn) * sinc(half_turn);
}

CantProfile::CantProfile(std::vector<CantElement> elements) : elements_(std::move(elements)) {
  s_start_ = {0.0};
  for (const CantElement& e : elements_)
    s_start_.push_back(s_start_.back() + e.length_m);
}

CantState CantProfile::at(double s) const {
  if (elements_.empty() || s < 0.0 || s > length())
    return {};
  const std::size_t i = indexIn(s_start_, s);
  const CantElement& e = elements_[i];
  const double d = e.cant_end_m - e.cant_start_m;
  if (d == 0.0 || e.length_m <= 0.0)
    return {e.cant_start_m, 0.0, 0.0};
  const double L = e.length_m;
  const double t = (s - s_start_[i]) / L;
  if (e.shape == RampShape::kLinear)
    return {e.cant_start_m + d * t, d / L, 0.0};
  return {e.cant_start_m + d * t * t * (3.0 - 2.0 * t), d * 6.0 * t * (1.0 - t) / L,
          d * 6.0 * (1.0 - 2.0 * t) / (L * L)};
}

}  // namespace trainsim::track
