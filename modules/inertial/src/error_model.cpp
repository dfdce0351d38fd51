#include "trainsim/inertial/error_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trainsim::inertial {
namespace {

// Per-run draws use an index no reading can reach.
constexpr std::uint64_t kRunIndex = ~std::uint64_t{0};

// A held flicker term is updated at least this many times per correlation time; a faster one
// is drawn at every reading.
constexpr double kHoldFraction = 10.0;

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
      slow_stream_(stream.seed(), stream.stream() ^ 0x736c6f77ULL),     // "slow"
      flicker_stream_(stream.seed(), stream.stream() ^ 0x666c6b72ULL),  // "flkr"
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

  // Flicker: GM terms one decade apart whose Allan-deviation peaks (at 1.89 T) sit at
  // τ0·10^{-3…4}; equal variances make their sum a 1/f spectrum between the outer poles, so the
  // floor is flat (within 2.5 %, closed form) from τ0/100 to 1000·τ0.
  white_ = spec.noise_density / std::sqrt(dt_);
  slow_ = spec.bias_instability > 0.0 || spec.random_walk > 0.0;
  const auto strideOf = [&](double period_s) {
    return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::floor(period_s / dt_)));
  };
  walk_stride_ = strideOf(kSlowStep_s);
  for (std::size_t i = 0; i < kFlickerTerms; ++i) {
    flicker_tau_[i] =
        spec.bias_instability_tau_s * std::pow(10.0, static_cast<double>(i) - 3.0) / 1.89;
    flicker_stride_[i] = strideOf(std::min(kSlowStep_s, flicker_tau_[i] / kHoldFraction));
    flicker_phi_[i] = std::exp(-static_cast<double>(flicker_stride_[i]) * dt_ / flicker_tau_[i]);
  }
  walk_step_ = spec.random_walk * std::sqrt(static_cast<double>(walk_stride_) * dt_);
  if (spec.bias_instability > 0.0) {
    double unit = 0.0;  // Allan variance at τ0 for σ = 1
    for (double t : flicker_tau_)
      unit += gaussMarkovAllanVariance(1.0, t, spec.bias_instability_tau_s);
    flicker_sigma_ = 0.664 * spec.bias_instability / std::sqrt(unit);
  }
  for (std::size_t i = 0; i < kFlickerTerms; ++i)
    flicker_q_[i] = flicker_sigma_ * std::sqrt(1.0 - flicker_phi_[i] * flicker_phi_[i]);
  // (Eigen leaves vectors uninitialised; unused terms are saved with a run's state.)
  flicker_.fill(Eigen::Vector3d::Zero());
  fast_value_.fill(Eigen::Vector3d::Zero());
  fast_innovation_.fill(Eigen::Vector3d::Zero());
  // Terms too fast to hold (T < kHoldFraction·dt) are drawn at every reading as what a reading
  // carries: their exact mean over the sample interval h (so the Allan variance at every τ = m·h is
  // the closed form's; a point sample would add white noise that is not in their spectrum). For an
  // Ornstein–Uhlenbeck process of variance σ² and φ = e^(−h/T), the interval means have
  // autocovariance γ0 = 2σ²T(h − T(1 − φ))/h², γj = σ²T²(1 − φ)²φ^(j−1)/h² (j ≥ 1): an
  // ARMA(1,1) sequence, y_k = φ y_{k−1} + e_k + θ e_{k−1}, which needs one normal per reading
  // and axis. White noise (σ_w² added to γ0) keeps that form, so it rides in the fastest term.
  for (std::size_t i = 0; i < kFlickerTerms; ++i) {
    const double t = flicker_tau_[i];
    if (!(flicker_sigma_ > 0.0 && t / kHoldFraction < dt_))
      break;
    fast_count_ = i + 1;
    const double s2 = flicker_sigma_ * flicker_sigma_, e = -std::expm1(-dt_ / t), h = dt_;
    const double phi = 1.0 - e;
    const double g0 = 2.0 * s2 * t * (h - t * e) / (h * h) + (i == 0 ? white_ * white_ : 0.0);
    const double g1 = s2 * t * t * e * e / (h * h);
    // The moving-average part u_k = y_k − φ y_{k−1}: c0 = (1 + φ²)γ0 − 2φγ1, c1 = γ1 − φγ0,
    // matched by σ_e²(1 + θ²) and σ_e²θ with |θ| < 1.
    const double c0 = (1.0 + phi * phi) * g0 - 2.0 * phi * g1, c1 = g1 - phi * g0;
    const double rho = std::clamp(c1 / c0, -0.5, 0.5);
    const double theta = rho == 0.0 ? 0.0 : (1.0 - std::sqrt(1.0 - 4.0 * rho * rho)) / (2.0 * rho);
    FastTerm& f = fast_[i];
    f.phi = phi;
    f.theta = theta;
    f.sigma = std::sqrt(c0 / (1.0 + theta * theta));
    f.start = std::sqrt(std::max(0.0, g0 - f.sigma * f.sigma));
  }
}

double TriadErrorModel::flickerAllanVariance(double tau_s) const {
  double sum = 0.0;
  for (double t : flicker_tau_)
    sum += gaussMarkovAllanVariance(flicker_sigma_, t, tau_s);
  return sum;
}

bool TriadErrorModel::due(std::uint64_t k, std::uint64_t stride, std::uint64_t& next) {
  // At the multiples of the stride (a pure function of k, so a resumed run keeps the same
  // schedule); `next` is the next multiple, and the division is only done when a reading is
  // not the expected next one.
  if (k < next)
    return false;
  const bool at_multiple = k == next || k % stride == 0;
  next = k == next ? next + stride : (k / stride + 1) * stride;
  return at_multiple;
}

void TriadErrorModel::updateHeldTerms(std::uint64_t k) {
  // Each held term is discretised exactly over its own stride and held in between; the
  // numbers are keyed by the reading index (and term), on streams apart from the white noise.
  bool changed = false;
  if (spec_.random_walk > 0.0 && due(k, walk_stride_, walk_next_)) {
    double w[3];
    slow_stream_.normals(k, w, 3);
    for (int a = 0; a < 3; ++a)
      walk_[a] += walk_step_ * w[a];
    changed = true;
  }
  if (flicker_sigma_ > 0.0) {
    for (std::size_t i = fast_count_; i < kFlickerTerms; ++i) {
      if (!due(k, flicker_stride_[i], flicker_next_[i]))
        continue;
      double w[3];
      flicker_stream_.normals(k * kFlickerTerms + i, w, 3);
      for (int a = 0; a < 3; ++a)
        flicker_[i][a] = flicker_phi_[i] * flicker_[i][a] + flicker_q_[i] * w[a];
      changed = true;
    }
  }
  if (changed)
    sumHeldTerms();
  updateNextHeld();
}

void TriadErrorModel::updateNextHeld() {
  next_held_ = spec_.random_walk > 0.0 ? walk_next_ : std::numeric_limits<std::uint64_t>::max();
  if (flicker_sigma_ > 0.0)
    for (std::size_t i = fast_count_; i < kFlickerTerms; ++i)
      next_held_ = std::min(next_held_, flicker_next_[i]);
}

Eigen::Vector3d TriadErrorModel::fastTerms(std::uint64_t k) {
  // Three normals per fast term at reading k, from the white-noise stream (the white noise
  // rides in term 0).
  double z[3 * kFlickerTerms];
  stream_.normals(k, z, 3 * fast_count_);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < fast_count_; ++i) {
    const FastTerm& f = fast_[i];
    const Eigen::Vector3d e = f.sigma * Eigen::Vector3d(z[3 * i], z[3 * i + 1], z[3 * i + 2]);
    fast_value_[i] = f.phi * fast_value_[i] + e + f.theta * fast_innovation_[i];
    fast_innovation_[i] = e;
    sum += fast_value_[i];
  }
  return sum;
}

void TriadErrorModel::resetSchedule(std::uint64_t from) {
  // Every held term due at its first multiple of the stride from `from` on.
  const auto first = [&](std::uint64_t stride) { return (from + stride - 1) / stride * stride; };
  walk_next_ = first(walk_stride_);
  for (std::size_t i = 0; i < kFlickerTerms; ++i)
    flicker_next_[i] = first(flicker_stride_[i]);
  updateNextHeld();
}

void TriadErrorModel::sumHeldTerms() {
  held_sum_ = walk_;
  for (std::size_t i = fast_count_; i < kFlickerTerms; ++i)
    held_sum_ += flicker_[i];
}

Eigen::Vector3d TriadErrorModel::measure(std::uint64_t k, const Eigen::Vector3d& x,
                                         const Eigen::Vector3d& f, double temperature_offset_k) {
  if (!started_) {
    // Stationary start of the GM terms, drawn from the per-run stream.
    const std::array<double, 24> init = normals(stream_, kRunIndex - 1);
    for (std::size_t i = 0; i < kFlickerTerms; ++i)
      for (int a = 0; a < 3; ++a)
        flicker_[i][a] = flicker_sigma_ * init[3 * i + static_cast<std::size_t>(a)];
    // The fast terms' last value and innovation, jointly stationary: e ~ N(0, σ_e²) and
    // y = e + √(γ0 − σ_e²)·z.
    std::array<double, 6 * kFlickerTerms> z{};
    stream_.normals(kRunIndex - 2, z.data(), 6 * fast_count_);
    for (std::size_t i = 0; i < fast_count_; ++i)
      for (int a = 0; a < 3; ++a) {
        const double e = fast_[i].sigma * z[6 * i + static_cast<std::size_t>(a)];
        fast_innovation_[i][a] = e;
        fast_value_[i][a] = e + fast_[i].start * z[6 * i + 3 + static_cast<std::size_t>(a)];
      }
    started_ = true;
    sumHeldTerms();
    resetSchedule(k + 1);
  } else if (slow_ && k >= next_held_) {
    updateHeldTerms(k);
  }
  Eigen::Vector3d bias = turn_on_ + held_sum_;
  if (spec_.temperature_coefficient != 0.0)
    bias.array() += spec_.temperature_coefficient * temperature_offset_k;
  last_bias_ = bias;
  Eigen::Vector3d y = x + m_ * x + bias;
  if (spec_.g_sensitivity > 0.0)
    y += g_ * f;
  if (fast_count_ > 0) {
    y += fastTerms(k);  // white noise included
  } else if (white_ > 0.0) {
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
  const auto list = [](const auto& vectors) {
    nlohmann::json out = nlohmann::json::array();
    for (const Eigen::Vector3d& v : vectors)
      out.push_back({v.x(), v.y(), v.z()});
    return out;
  };
  return {{"started", started_},
          {"flicker", list(flicker_)},
          {"fast_value", list(fast_value_)},
          {"fast_innovation", list(fast_innovation_)},
          {"walk", {walk_.x(), walk_.y(), walk_.z()}},
          {"residual", {residual_.x(), residual_.y(), residual_.z()}}};
}

void TriadErrorModel::restore(const nlohmann::json& s) {
  const auto read = [&](const char* key, auto& vectors) {
    for (std::size_t i = 0; i < vectors.size(); ++i)
      for (std::size_t a = 0; a < 3; ++a)
        vectors[i][static_cast<int>(a)] = s.at(key).at(i).at(a).template get<double>();
  };
  resetSchedule(0);
  started_ = s.at("started").get<bool>();
  read("flicker", flicker_);
  read("fast_value", fast_value_);
  read("fast_innovation", fast_innovation_);
  for (std::size_t a = 0; a < 3; ++a) {
    walk_[static_cast<int>(a)] = s.at("walk").at(a).get<double>();
    residual_[static_cast<int>(a)] = s.at("residual").at(a).get<double>();
  }
  sumHeldTerms();
}

}  // namespace trainsim::inertial
