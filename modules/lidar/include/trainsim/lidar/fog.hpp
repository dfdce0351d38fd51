#pragma once
// Fog in a LiDAR's path, after Rasshofer et al. 2011 ("Influences of weather phenomena on
// automotive laser radar systems", Adv. Radio Sci. 9) as Hahner et al. 2021 ("Fog Simulation on
// Real LiDAR Point Clouds for 3D Object Detection in Adverse Weather", ICCV) apply it to an
// HDL-64E: the fog dims every echo by its two-way transmission e^(−2 τ), and it is itself a
// "soft target" whose backscatter the receiver sees as one broad echo a few metres out.
#include <vector>

namespace trainsim::lidar {

struct FogParams {
  /// Meteorological visibility at the sensor (Koschmieder, 2 % contrast); 0: clear air.
  double visibility_m = 0.0;
  /// The layer's scale height (scene::fogDepth): the fog thins by e every this many metres
  /// above the sensor.
  double height_m = 100.0;
  /// The pulse's half-power width τ_H: the transmitted power is P₀ sin²(π t / 2τ_H) over
  /// 0 ≤ t ≤ 2τ_H. 20 ns is Hahner et al.'s value for the HDL-64E [unverified for the others].
  double pulse_half_width_ns = 20.0;
  /// The receiver's field of view starts to overlap the beam at overlap_begin_m and covers it
  /// from overlap_full_m on (ξ(R) rises linearly between them): a biaxial sensor is blind to
  /// what lies nearer. The fog's echo comes mostly from its first metres (its backscatter falls
  /// as 1 / R²), so the overlap sets how strong it is. Hahner et al. take 0.9 and 1.0 m and
  /// note that most sensors reach full overlap within 10 m; TrainSim's default is that 10 m
  /// [unverified per device]: with 1 m an HDL-64E's sky would return fog in 1 km of visibility.
  double overlap_begin_m = 0.9, overlap_full_m = 10.0;
  bool on() const { return visibility_m > 0.0; }
};

/// The fog's effect on a pulse, worked out once for a sensor. Powers are in the LiDAR's units
/// of reflectivity over range squared (LidarParams::detectable()): a Lambertian target of
/// reflectivity ρ head-on at range R in clear air returns ρ / R², which is π β₀ / R² with its
/// differential reflectivity β₀ = ρ / π.
class FogModel {
 public:
  FogModel() = default;
  explicit FogModel(const FogParams& params);
  const FogParams& params() const { return params_; }
  bool on() const { return params_.on(); }
  /// Extinction α at the sensor (1/m): 3.912 / visibility.
  double extinction() const { return alpha_; }
  /// Backscattering coefficient β (1/(m sr)): 0.046 / MOR with MOR = ln 20 / α, the 5 %
  /// contrast visibility Rasshofer et al.'s figure is given for.
  double backscattering() const { return beta_; }
  /// The two-way transmission e^(−2 τ) to `range_m` along a ray of elevation sine
  /// `sin_elevation` (scene::fogDepth's layer); 1 in clear air.
  double transmission(double range_m, double sin_elevation) const;
  /// The received power of the fog's own backscatter at range R in fog as thick as at the
  /// sensor throughout (Rasshofer's soft-target response, in the units above):
  ///   π β ∫ sin²(π (R − r) / cτ_H) ξ(r) e^(−2 α r) / r² dr over r in [R − cτ_H, R],
  /// from the table worked out at construction (linear between its 1 cm steps).
  double response(double range_m) const;
  /// The waveform's peak: its power and range. The receiver reports the fog as one echo.
  double peakPower() const { return peak_power_; }
  double peakRange() const { return peak_range_; }
  /// The span around the peak where the waveform is above half its peak power. The echo's
  /// range is drawn in it, with density ∝ response() (the droplets' speckle moves the detected
  /// peak from pulse to pulse: the fog's points form a shell as thick as the waveform's top,
  /// not a sphere at one range).
  double nearRange() const { return near_; }
  double farRange() const { return far_; }
  /// The echo's range for a uniform draw u in [0, 1).
  double drawRange(double u) const;
  /// How dense the fog is at `range_m` along a ray of elevation sine `sin_elevation`, relative to
  /// the sensor (1 below it): the fog's echo, worked out for the fog at the sensor, is scaled by
  /// it where it is drawn.
  double density(double range_m, double sin_elevation) const;

 private:
  FogParams params_;
  double alpha_ = 0.0, beta_ = 0.0;
  std::vector<double> response_;  // at range i · 1 cm
  double peak_power_ = 0.0, peak_range_ = 0.0, near_ = 0.0, far_ = 0.0;
  std::vector<double> cdf_;  // over [near_, far_] at 1 cm steps, from 0 to 1
};

}  // namespace trainsim::lidar
