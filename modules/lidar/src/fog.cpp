#include "trainsim/lidar/fog.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/core/error.hpp"
#include "trainsim/scene/atmosphere.hpp"

namespace trainsim::lidar {
namespace {
constexpr double kSpeedOfLight = 299'792'458.0;  // m/s
// Rasshofer et al. 2011: fog's backscattering coefficient is 0.046 / MOR (1/(m sr)).
constexpr double kBackscatterTimesMor = 0.046;
// The soft-target integral's step: the integrand's kinks (where the overlap starts and ends)
// cost the trapezoid rule O(h²) there, under 1e-6 of the response at 1 mm.
constexpr double kInnerStep = 0.001;
// The response table's step (m).
constexpr double kStep = 0.01;
}  // namespace

FogModel::FogModel(const FogParams& params) : params_(params) {
  if (!params_.on())
    return;
  const FogParams& p = params_;
  if (!(p.height_m > 0.0) || !(p.pulse_half_width_ns > 0.0) || !(p.overlap_begin_m >= 0.0) ||
      !(p.overlap_full_m > p.overlap_begin_m))
    throw ConfigError(
        "LiDAR fog: the height and the pulse width must be positive and the overlap must end "
        "beyond where it begins");
  alpha_ = scene::fogExtinction(p.visibility_m);
  beta_ = kBackscatterTimesMor * alpha_ / std::log(20.0);
  // The pulse's length in range: the sin² pulse lasts 2 τ_H, and a round trip halves it.
  const double L = kSpeedOfLight * p.pulse_half_width_ns * 1e-9;
  // What the integrand holds but for the pulse: ξ(r) e^(−2 α r) / r², on a fine grid from where
  // the overlap begins; and the pulse sin²(π x / L) over x in [0, L] on the same grid (zero, with
  // its slope, at both ends, so the window's ends need no care).
  const auto inner = [](double length) { return static_cast<std::size_t>(length / kInnerStep); };
  const double r0 = p.overlap_begin_m, end = p.overlap_full_m + 4.0 * L;
  std::vector<double> g(inner(end - r0) + 2);
  for (std::size_t j = 0; j < g.size(); ++j) {
    const double r = r0 + static_cast<double>(j) * kInnerStep;
    const double xi = std::min(1.0, (r - r0) / (p.overlap_full_m - r0));
    g[j] = r > 0.0 ? xi * std::exp(-2.0 * alpha_ * r) / (r * r) : 0.0;
  }
  std::vector<double> pulse(inner(L) + 1);
  for (std::size_t j = 0; j < pulse.size(); ++j) {
    const double s = std::sin(std::numbers::pi * static_cast<double>(j) * kInnerStep / L);
    pulse[j] = s * s;
  }
  const auto rows = static_cast<std::size_t>(end / kStep) + 1;
  response_.assign(rows, 0.0);
  const auto per_row = static_cast<std::size_t>(std::lround(kStep / kInnerStep));
  const auto first = static_cast<std::size_t>(std::lround(r0 / kInnerStep));
  for (std::size_t i = 0; i < rows; ++i) {
    // R = i · kStep is grid point k = i · per_row of a grid from 0; g's point j is k = first + j.
    const std::size_t k = i * per_row;
    if (k <= first)
      continue;
    double sum = 0.0;
    for (std::size_t x = 0; x < pulse.size() && x + first < k; ++x) {
      const std::size_t j = k - x - first;
      if (j < g.size())
        sum += pulse[x] * g[j];
    }
    response_[i] = std::numbers::pi * beta_ * sum * kInnerStep;
  }
  const auto peak = static_cast<std::size_t>(std::max_element(response_.begin(), response_.end()) -
                                             response_.begin());
  peak_power_ = response_[peak];
  peak_range_ = static_cast<double>(peak) * kStep;
  std::size_t lo = peak, hi = peak;
  while (lo > 0 && response_[lo - 1] >= 0.5 * peak_power_)
    --lo;
  while (hi + 1 < rows && response_[hi + 1] >= 0.5 * peak_power_)
    ++hi;
  near_ = static_cast<double>(lo) * kStep;
  far_ = static_cast<double>(hi) * kStep;
  cdf_.assign(hi - lo + 1, 0.0);
  for (std::size_t i = lo + 1; i <= hi; ++i)
    cdf_[i - lo] = cdf_[i - lo - 1] + 0.5 * (response_[i - 1] + response_[i]);
  if (cdf_.back() > 0.0)
    for (double& c : cdf_)
      c /= cdf_.back();
}

double FogModel::transmission(double range_m, double sin_elevation) const {
  if (!on())
    return 1.0;
  return std::exp(-2.0 * scene::fogDepth(alpha_, params_.height_m, range_m, sin_elevation));
}

double FogModel::response(double range_m) const {
  if (response_.empty() || !(range_m >= 0.0))
    return 0.0;
  const double x = range_m / kStep;
  const auto i = static_cast<std::size_t>(x);
  if (i + 1 >= response_.size())
    return i + 1 == response_.size() ? response_.back() : 0.0;
  const double f = x - static_cast<double>(i);
  return (1.0 - f) * response_[i] + f * response_[i + 1];
}

double FogModel::drawRange(double u) const {
  if (cdf_.size() < 2)
    return peak_range_;
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const auto i = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(
      it - cdf_.begin(), 1, static_cast<std::ptrdiff_t>(cdf_.size()) - 1));
  const double span = cdf_[i] - cdf_[i - 1];
  const double f = span > 0.0 ? std::clamp((u - cdf_[i - 1]) / span, 0.0, 1.0) : 0.0;
  return near_ + (static_cast<double>(i - 1) + f) * kStep;
}

double FogModel::density(double range_m, double sin_elevation) const {
  return sin_elevation > 0.0 ? std::exp(-range_m * sin_elevation / params_.height_m) : 1.0;
}

}  // namespace trainsim::lidar
