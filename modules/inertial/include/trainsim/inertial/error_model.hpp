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
  double bias_instability_tau_s = 100;  ///< cluster time at the middle of the flat floor
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
/// instability as a sum of five first-order Gauss–Markov processes with log-spaced correlation
/// times (a flicker approximation whose Allan deviation is flat at 0.664·B over about two
/// decades around `bias_instability_tau_s`; one GM process would give a hump), rate random
/// walk, white noise, saturation and quantization with the residual carried over. All
/// processes are discretised exactly, so the statistics do not depend on the sample rate.
/// The slow terms (bias instability, random walk) are updated every `slowStride()` readings,
/// about every 0.25 s and never more than 1/20 of the shortest flicker correlation time, and
/// held in between: their spectrum lies far below the sample rate, and drawing their 18
/// normals at every reading would cost most of the model's time. White noise is drawn at
/// every reading with the keyed ziggurat (RandomStream::normals).
/// Random numbers are keyed by (seed, stream, reading index): a run is reproducible and can
/// resume from state().
class TriadErrorModel {
 public:
  static constexpr int kFlickerTerms = 5;

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
  std::uint64_t slowStride() const { return stride_; }
  const std::array<double, kFlickerTerms>& flickerTau() const { return flicker_tau_; }

 private:
  TriadSpec spec_;
  RandomStream stream_;
  RandomStream slow_stream_;
  double dt_;
  double white_ = 0.0;  // σ per reading
  Eigen::Matrix3d m_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d g_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d turn_on_ = Eigen::Vector3d::Zero();
  double flicker_sigma_ = 0.0;
  std::array<double, kFlickerTerms> flicker_tau_{};
  std::array<double, kFlickerTerms> flicker_phi_{};  // over one stride
  std::uint64_t stride_ = 1;
  // Running state.
  std::array<Eigen::Vector3d, kFlickerTerms> flicker_{};
  Eigen::Vector3d walk_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d residual_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_bias_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d slow_sum_ = Eigen::Vector3d::Zero();  // walk + flicker terms
  std::uint64_t next_slow_ = 0;                         // next reading due a slow update
  bool slow_ = false;
  bool started_ = false;
};

/// Allan variance of a first-order Gauss–Markov process of variance σ² and correlation time
/// T at cluster time τ: (2σ²T/τ)·[1 − (T/2τ)(3 − 4e^(−τ/T) + e^(−2τ/T))].
double gaussMarkovAllanVariance(double sigma, double tau_c, double tau);

/// Overlapping Allan deviation of a rate signal sampled every dt at cluster size m
/// (τ = m·dt), from its running integral (docs/REFERENCES.md R2.1).
double allanDeviation(const std::vector<double>& rate, double dt, std::size_t m);

}  // namespace trainsim::inertial
