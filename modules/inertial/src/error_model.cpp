#include "trainsim/inertial/error_model.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::inertial {
namespace {

// Per-run draws use an index no reading can reach.
constexpr std::uint64_t kRunIndex = ~std::uint64_t{0};

// 24 standard normals for (index, blocks 0..5).
std::array<double, 24> normals(const RandomStream& s, std::uint64_t index) {
  std::array<double, 24> out{};
  for (std::uint64_t b = 0; b < 6; ++b) {
    const auto n = s.normal4(index, b);
    std::copy(n.begin(), n.end(), out.begin() + static_cast<std::ptrdiff_t>(4 * b));
  }
  return out;
}

}  // namespace

double gaussMarkovAllanVariance(double sigma, double tau_c, double tau) {
  const double x = tau / tau_c;
  if (x < 1e-3)  // series, avoiding the cancellation in 3 − 4e^(−x) + e^(−2x) ≈ 2x
    return sigma * sigma * (2.0 * x / 3.0 - x * x / 2.0);
  return 2.0 * sigma * sigma / x *
         (1.0 - (3.0 - 4.0 * std::exp(-x) + std::exp(-2.0 * x)) / (2.0 * x));
}

double allanDeviation(const std::vector<double>& rate, double dt, std::size_t m) {
  const std::size_t n = rate.size();
  if (m == 0 || 2 * m >= n)
    return 0.0;
  std::vector<double> theta(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    theta[i + 1] = theta[i] + rate[i] * dt;
  const double tau = static_cast<double>(m) * dt;
  long double sum = 0.0L;
  const std::size_t count = n + 1 - 2 * m;
  for (std::size_t k = 0; k < count; ++k) {
    const double d = theta[k + 2 * m] - 2.0 * theta[k + m] + theta[k];
    sum += static_cast<long double>(d) * d;
  }
  return std::sqrt(static_cast<double>(sum / (2.0L * tau * tau * count)));
}

TriadErrorModel::TriadErrorModel(const TriadSpec& spec, const RandomStream& stream, double dt_s)
    : spec_(spec),
      stream_(stream),
      slow_stream_(stream.seed(), stream.stream() ^ 0x736c6f77ULL),  // "slow"
      dt_(dt_s) {
  const std::array<double, 24> run = normals(stream_, kRunIndex);
  for (int i = 0; i < 3; ++i) {
    turn_on_[i] = spec.turn_on_bias * run[static_cast<std::size_t>(i)];
    m_(i, i) = spec.scale_factor * run[static_cast<std::size_t>(3 + i)];
  }
  const int off[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  for (int j = 0; j < 6; ++j)
    m_(off[j][0], off[j][1]) = spec.misalignment_rad * run[static_cast<std::size_t>(6 + j)];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      g_(i, j) = spec.g_sensitivity * run[static_cast<std::size_t>(12 + 3 * i + j)];

  // Flicker: five GM terms whose Allan-deviation peaks (at 1.89 T) sit at τ0·10^{-1…1}.
  white_ = spec.noise_density / std::sqrt(dt_);
  slow_ = spec.bias_instability > 0.0 || spec.random_walk > 0.0;
  for (int i = 0; i < kFlickerTerms; ++i)
    flicker_tau_[static_cast<std::size_t>(i)] =
        spec.bias_instability_tau_s * std::pow(10.0, 0.5 * (i - 2)) / 1.89;
  const double slow_step = std::min(0.25, flicker_tau_[0] / 20.0);
  stride_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::floor(slow_step / dt_)));
  for (std::size_t i = 0; i < kFlickerTerms; ++i)
    flicker_phi_[i] = std::exp(-static_cast<double>(stride_) * dt_ / flicker_tau_[i]);
  if (spec.bias_instability > 0.0) {
    double unit = 0.0;  // Allan variance at τ0 for σ = 1
    for (double t : flicker_tau_)
      unit += gaussMarkovAllanVariance(1.0, t, spec.bias_instability_tau_s);
    flicker_sigma_ = 0.664 * spec.bias_instability / std::sqrt(unit);
  }
}

Eigen::Vector3d TriadErrorModel::measure(std::uint64_t k, const Eigen::Vector3d& x,
                                         const Eigen::Vector3d& f, double temperature_offset_k) {
  if (!started_) {
    // Stationary start of the GM terms, drawn from the per-run stream.
    const std::array<double, 24> init = normals(stream_, kRunIndex - 1);
    for (std::size_t i = 0; i < kFlickerTerms; ++i)
      for (int a = 0; a < 3; ++a)
        flicker_[i][a] = flicker_sigma_ * init[3 * i + static_cast<std::size_t>(a)];
    started_ = true;
    slow_sum_ = walk_;
    for (const Eigen::Vector3d& b : flicker_)
      slow_sum_ += b;
  } else if (slow_ && k >= next_slow_ && k % stride_ == 0) {
    // Slow terms, exactly discretised over one stride (keyed by the reading index; a
    // separate stream from the white noise).
    std::array<double, 24> w{};
    slow_stream_.normals(k, w.data(), 6 + 3 * kFlickerTerms);
    for (std::size_t i = 0; i < kFlickerTerms; ++i) {
      const double q = flicker_sigma_ * std::sqrt(1.0 - flicker_phi_[i] * flicker_phi_[i]);
      for (int a = 0; a < 3; ++a)
        flicker_[i][a] =
            flicker_phi_[i] * flicker_[i][a] + q * w[6 + 3 * i + static_cast<std::size_t>(a)];
    }
    const double step = std::sqrt(static_cast<double>(stride_) * dt_);
    for (int a = 0; a < 3; ++a)
      walk_[a] += spec_.random_walk * step * w[3 + static_cast<std::size_t>(a)];
    slow_sum_ = walk_;
    for (const Eigen::Vector3d& b : flicker_)
      slow_sum_ += b;
  }
  // The next update is due at the next multiple of the stride (a pure function of k, so a
  // resumed run keeps the same schedule; the modulo is only taken once per stride).
  if (k >= next_slow_)
    next_slow_ = (k / stride_ + 1) * stride_;
  Eigen::Vector3d bias = turn_on_ + slow_sum_;
  if (spec_.temperature_coefficient != 0.0)
    bias.array() += spec_.temperature_coefficient * temperature_offset_k;
  last_bias_ = bias;
  Eigen::Vector3d y = x + m_ * x + bias;
  if (spec_.g_sensitivity > 0.0)
    y += g_ * f;
  if (white_ > 0.0) {
    double n[3];
    stream_.normals(k, n, 3);
    y += white_ * Eigen::Vector3d(n[0], n[1], n[2]);
  }
  for (int a = 0; a < 3; ++a) {
    y[a] = std::clamp(y[a], -spec_.range, spec_.range);
    if (spec_.resolution > 0.0) {
      const double v = y[a] + residual_[a];
      const double q = spec_.resolution * std::round(v / spec_.resolution);
      residual_[a] = v - q;
      y[a] = q;
    }
  }
  return y;
}

nlohmann::json TriadErrorModel::state() const {
  nlohmann::json flicker = nlohmann::json::array();
  for (const Eigen::Vector3d& b : flicker_)
    flicker.push_back({b.x(), b.y(), b.z()});
  return {{"started", started_},
          {"flicker", flicker},
          {"walk", {walk_.x(), walk_.y(), walk_.z()}},
          {"residual", {residual_.x(), residual_.y(), residual_.z()}}};
}

void TriadErrorModel::restore(const nlohmann::json& s) {
  next_slow_ = 0;
  started_ = s.at("started").get<bool>();
  for (std::size_t i = 0; i < kFlickerTerms; ++i)
    for (std::size_t a = 0; a < 3; ++a)
      flicker_[i][static_cast<int>(a)] = s.at("flicker").at(i).at(a).get<double>();
  for (std::size_t a = 0; a < 3; ++a) {
    walk_[static_cast<int>(a)] = s.at("walk").at(a).get<double>();
    residual_[static_cast<int>(a)] = s.at("residual").at(a).get<double>();
  }
  slow_sum_ = walk_;
  for (const Eigen::Vector3d& b : flicker_)
    slow_sum_ += b;
}

}  // namespace trainsim::inertial
