#include "trainsim/positioning/balise.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::positioning {

std::vector<Balise> placeBalises(const BalisePlacement& p, double track_length_m,
                                 std::span<const double> station_starts_m) {
  std::vector<double> groups;
  const double group_length = p.balise_spacing_m * p.balises_per_group;
  for (double u = p.first_group_m; u + group_length < track_length_m; u += p.group_spacing_m)
    groups.push_back(u);
  if (p.station_approach_m > 0.0)
    for (double start : station_starts_m) {
      const double u = start - p.station_approach_m;
      if (u > 0.0)
        groups.push_back(u);
    }
  std::sort(groups.begin(), groups.end());
  std::vector<Balise> out;
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (int i = 0; i < p.balises_per_group; ++i)
      out.push_back({static_cast<int>(g), i, groups[g] + p.balise_spacing_m * i});
  return out;
}

TimeNs passageTime(const AntennaState& a, const AntennaState& b, double target_m) {
  const double h = toSeconds(b.t - a.t);
  auto u = [&](double x) {
    const double x2 = x * x, x3 = x2 * x;
    return (2 * x3 - 3 * x2 + 1) * a.u_m + (x3 - 2 * x2 + x) * h * a.v_m_s +
           (-2 * x3 + 3 * x2) * b.u_m + (x3 - x2) * h * b.v_m_s;
  };
  // Bisection to below a nanosecond for any interval shorter than 2^60 ns.
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (u(mid) < target_m ? lo : hi) = mid;
  }
  return a.t + static_cast<TimeNs>(std::llround(hi * static_cast<double>(b.t - a.t)));
}

BaliseDetector::BaliseDetector(std::vector<Balise> balises, double detection_sigma_m,
                               RandomStream random)
    : balises_(std::move(balises)), detection_sigma_m_(detection_sigma_m), random_(random) {}

std::vector<BaliseEvent> BaliseDetector::step(const AntennaState& now) {
  std::vector<BaliseEvent> events;
  if (!started_) {
    while (next_ < balises_.size() && balises_[next_].u_m <= now.u_m)
      ++next_;
    started_ = true;
    previous_ = now;
    return events;
  }
  while (next_ < balises_.size()) {
    const Balise& b = balises_[next_];
    const double error = detection_sigma_m_ * random_.normal4(static_cast<std::uint64_t>(next_))[0];
    const double at = b.u_m + error;
    if (at > now.u_m)
      break;
    events.push_back({passageTime(previous_, now, std::max(at, previous_.u_m)), &b});
    ++next_;
  }
  previous_ = now;
  return events;
}

nlohmann::json BaliseDetector::state() const {
  return {{"t_ns", previous_.t}, {"u", previous_.u_m}, {"v", previous_.v_m_s}, {"next", next_}};
}

void BaliseDetector::restore(const nlohmann::json& state) {
  previous_ = {state.at("t_ns").get<TimeNs>(), state.at("u").get<double>(),
               state.at("v").get<double>()};
  next_ = state.at("next").get<std::size_t>();
  started_ = true;
}

}  // namespace trainsim::positioning
