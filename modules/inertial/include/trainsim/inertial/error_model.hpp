#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string_view>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "trainsim/core/random.hpp"

namespace trainsim::inertial {

/// Error parameters of one sensor triad (accelerometer: m/s²; gyroscope: rad/s; magnetometer:
/// T), IEEE-952 terms (docs/REFERENCES.md R2.1–R2.3). Zero switches a term off.
struct TriadSpec {
  double noise_density = 0.0;           ///< white noise N, unit/√Hz: σ = N·√f_s per sample
  double random_walk = 0.0;             ///< rate random walk K, unit/√s (ADEV K·√(τ/3))
  double bias_instability = 0.0;        ///< B, unit: ADEV floor ≈ 0.664·B
  double bias_instability_tau_s = 100;  ///< τ0: floor 0.664·B flat over τ0/100…1000·τ0
  double turn_on_bias = 0.0;            ///< 1σ of the per-run constant bias, unit
  double scale_factor = 0.0;            ///< 1σ of the per-run scale-factor error (ratio)
  double misalignment_rad = 0.0;        ///< 1σ of each per-run cross-axis coupling term
  double g_sensitivity = 0.0;           ///< gyroscope only: 1σ of each G term, (rad/s)/(m/s²)
  double range = std::numeric_limits<double>::infinity();  ///< saturation at ±range
  double resolution = 0.0;               ///< LSB; quantization carries the residual over
  double temperature_coefficient = 0.0;  ///< bias per kelvin of (T − T_ref)
};

/// The output chain of one triad, y = Q(sat((I + M)·x + G·f + b_on + b_BI + b_RW + b_T + n)):
/// misalignment and scale factor M, g-sensitivity G (gyroscope), turn-on bias, bias
/// instability, rate random walk, white noise, saturation and quantization with the residual
/// carried over. All processes are discretised exactly, so the statistics do not depend on the
/// sample rate.
///
/// Bias instability is flicker (1/f) noise, approximated by eight first-order Gauss–Markov
/// processes of equal variance whose correlation times are one decade apart,
/// T_i = τ0·10^(i−3)/1.89 for i = 0…7 (τ0 = `bias_instability_tau_s`; a GM process's Allan
/// deviation peaks at τ = 1.89 T). Their Allan deviation is 0.664·B at τ0 and flat within
/// 2.5 % from τ0/100 to 1000·τ0 (flickerAllanVariance, the closed form): it reaches past the
/// random-walk line of any sensor, whose slow bias wander is then 1/f down to ~10⁻⁵/τ0 Hz.
/// Below τ0/100 it falls off as τ^(+1/2), where white noise dominates a real sensor. One GM
/// process would give a hump, not a floor.
///
/// The slow terms are held between updates: the random walk is updated every 0.25 s, each
/// flicker term every 1/20 of its correlation time (at most 0.25 s), their spectra lying far
/// below those rates. A flicker term faster than that is advanced at every reading and gives
/// its exact mean over the sample interval, as white noise does (σ = N/√dt is the interval
/// mean of white noise), so the Allan variance at every τ = m·dt is the closed form's. White noise
/// is drawn at every reading with the keyed ziggurat (RandomStream::normals). Random numbers are
/// keyed by (seed, stream, reading index): a run is reproducible and can resume from state().
class TriadErrorModel {
 public:
  static constexpr std::size_t kFlickerTerms = 8;

  TriadErrorModel(const TriadSpec& spec, const RandomStream& stream, double dt_s);

  /// Output for reading `k` of true value `x` (and specific force `f` for g-sensitivity),
  /// with the temperature offset from the reference temperature in kelvin.
  Eigen::Vector3d measure(std::uint64_t k, const Eigen::Vector3d& x,
                          const Eigen::Vector3d& f = Eigen::Vector3d::Zero(),
                          double temperature_offset_k = 0.0);

  /// Total additive bias at the last reading (turn-on + instability + random walk +
  /// temperature), for ground-truth files.
  Eigen::Vector3d bias() const { return last_bias_; }
  const Eigen::Matrix3d& misalignment() const { return m_; }

  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

  /// Each flicker GM term's σ for a floor of 0.664·B (derived from the closed-form Allan
  /// variance of a GM process; exposed for tests).
  double flickerSigma() const { return flicker_sigma_; }
  const std::array<double, kFlickerTerms>& flickerTau() const { return flicker_tau_; }
  /// The closed-form Allan variance of the bias-instability terms at cluster time τ.
  double flickerAllanVariance(double tau_s) const;

 private:
  TriadSpec spec_;
  RandomStream stream_;
  RandomStream slow_stream_;
  RandomStream flicker_stream_;
  double dt_;
  double white_ = 0.0;  // σ per reading
  Eigen::Matrix3d m_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d g_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d turn_on_ = Eigen::Vector3d::Zero();
  double flicker_sigma_ = 0.0;
  std::array<double, kFlickerTerms> flicker_tau_{};
  std::array<double, kFlickerTerms> flicker_phi_{};  // over one stride
  std::array<double, kFlickerTerms> flicker_q_{};    // σ√(1 − φ²): the innovation's σ
  std::array<std::uint64_t, kFlickerTerms> flicker_stride_{};
  std::uint64_t walk_stride_ = 1;
  double walk_step_ = 0.0;  // K√(stride·dt)
  // Running state.
  std::array<Eigen::Vector3d, kFlickerTerms> flicker_{};  // held terms: value at last update
  // Fast terms: the last interval mean and innovation of each ARMA(1,1) sequence.
  std::array<Eigen::Vector3d, kFlickerTerms> fast_value_{}, fast_innovation_{};
  Eigen::Vector3d walk_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d residual_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_bias_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d held_sum_ = Eigen::Vector3d::Zero();  // walk + held flicker terms
  std::uint64_t next_held_ = 0;  // next reading due a held update (of any term)
  std::uint64_t walk_next_ = 0;  // and of each term
  std::array<std::uint64_t, kFlickerTerms> flicker_next_{};
  bool slow_ = false;
  bool started_ = false;

  static constexpr double kSlowStep_s = 0.25;
  // A flicker term drawn at every reading as the ARMA(1,1) sequence of its interval means
  // (see the constructor); term 0 carries the white noise too.
  struct FastTerm {
    double phi = 0.0, theta = 0.0, sigma = 0.0;  // y_k = φ y_{k−1} + e_k + θ e_{k−1}, e ~ σ
    double start = 0.0;                          // √(γ0 − σ²) for a stationary start
  };
  std::array<FastTerm, kFlickerTerms> fast_{};
  std::size_t fast_count_ = 0;  // terms 0 … fast_count_ − 1 are fast (the shortest T first)
  static bool due(std::uint64_t k, std::uint64_t stride, std::uint64_t& next);
  void resetSchedule(std::uint64_t from);
  void updateHeldTerms(std::uint64_t k);
  void updateNextHeld();
  Eigen::Vector3d fastTerms(std::uint64_t k);
  void sumHeldTerms();
};

/// Allan variance of a first-order Gauss–Markov process of variance σ² and correlation time
/// T at cluster time τ: (2σ²T/τ)·[1 − (T/2τ)(3 − 4e^(−τ/T) + e^(−2τ/T))].
double gaussMarkovAllanVariance(double sigma, double tau_c, double tau);

/// Overlapping Allan deviation of a rate signal sampled every dt at cluster size m
/// (τ = m·dt), from its running integral (docs/REFERENCES.md R2.1).
double allanDeviation(const std::vector<double>& rate, double dt, std::size_t m);

}  // namespace trainsim::inertial
