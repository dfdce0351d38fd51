#include "trainsim/positioning/gnss.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace trainsim::positioning {

GnssErrorModel::GnssErrorModel(const GnssErrorSpec& spec, TimeNs period, RandomStream random)
    : spec_(spec), random_(random), phi_(std::exp(-toSeconds(period) / spec.correlation_time_s)) {}

GnssErrors GnssErrorModel::step(std::uint64_t k) {
  // Draw blocks: 0 and 1 position (GM east/north/up, white east), 1 white north/up,
  // 2 white velocity, 3 velocity GM.
  const auto n = random_.normal4(k, 0);
  const auto m = random_.normal4(k, 1);
  const auto w = random_.normal4(k, 2);
  const auto vn = random_.normal4(k, 3);
  const double q = started_ ? std::sqrt(1 - phi_ * phi_) : 1.0;
  const double f = started_ ? phi_ : 0.0;
  const std::array<double, 3> sigma = {spec_.horizontal_sigma_m, spec_.horizontal_sigma_m,
                                       spec_.vertical_sigma_m};
  for (std::size_t a = 0; a < 3; ++a) {
    position_gm_[a] = f * position_gm_[a] + sigma[a] * q * n[a];
    velocity_gm_[a] = f * velocity_gm_[a] + spec_.velocity_gm_sigma_m_s * q * vn[a];
  }
  started_ = true;
  GnssErrors e;
  e.position_m = {position_gm_[0] + spec_.white_sigma_m * n[3],
                  position_gm_[1] + spec_.white_sigma_m * m[0],
                  position_gm_[2] + spec_.white_sigma_m * m[1]};
  for (std::size_t a = 0; a < 3; ++a)
    e.velocity_m_s[static_cast<Eigen::Index>(a)] =
        velocity_gm_[a] + spec_.velocity_sigma_m_s * w[a];
  return e;
}

nlohmann::json GnssErrorModel::state() const {
  return {{"gm", position_gm_}, {"vel_gm", velocity_gm_}, {"started", started_}};
}

void GnssErrorModel::restore(const nlohmann::json& state) {
  for (std::size_t a = 0; a < 3; ++a) {
    position_gm_[a] = state.at("gm").at(a).get<double>();
    velocity_gm_[a] = state.at("vel_gm").at(a).get<double>();
  }
  started_ = state.at("started").get<bool>();
}

GnssVisibility::GnssVisibility(std::vector<std::pair<double, double>> tunnels, TimeNs reacquisition)
    : tunnels_(std::move(tunnels)), reacquisition_(reacquisition) {}

std::vector<std::pair<double, double>>::const_iterator GnssVisibility::firstEndingFrom(
    double c) const {
  return std::lower_bound(tunnels_.begin(), tunnels_.end(), c,
                          [](const auto& tunnel, double x) { return tunnel.second < x; });
}

bool GnssVisibility::inTunnel(double c) const {
  const auto it = firstEndingFrom(c);
  return it != tunnels_.end() && it->first <= c;
}

bool GnssVisibility::fix(TimeNs t, const std::function<double(TimeNs)>& antenna_chainage) const {
  const double c = antenna_chainage(t);
  const auto it = firstEndingFrom(c);
  if (it != tunnels_.end() && it->first <= c)
    return false;  // inside
  if (it == tunnels_.begin() || reacquisition_ <= 0)
    return true;  // no tunnel behind
  // Left the last one behind at least `reacquisition` ago iff already past its end back then.
  return antenna_chainage(t - reacquisition_) > std::prev(it)->second;
}

}  // namespace trainsim::positioning
