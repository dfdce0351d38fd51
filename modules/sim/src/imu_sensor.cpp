#include "imu_sensor.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/inertial/earth.hpp"
#include "trainsim/inertial/error_model.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

using scenario::Json;
namespace units = scenario::units;

constexpr double kDeg = kRadPerDeg;
constexpr double kG = kStandardGravity_m_s2;

enum class ImuPreset { kIndustrial, kConsumer, kTactical, kIdeal, kCustom };
constexpr EnumName<ImuPreset> kImuPresetNames[] = {{ImuPreset::kIndustrial, "industrial"},
                                                   {ImuPreset::kConsumer, "consumer"},
                                                   {ImuPreset::kTactical, "tactical"},
                                                   {ImuPreset::kIdeal, "ideal"},
                                                   {ImuPreset::kCustom, "custom"}};
constexpr std::span<const EnumName<ImuPreset>> enumNames(ImuPreset) {
  return kImuPresetNames;
}

// Datasheet-class presets (docs/REFERENCES.md R2.4; values marked [std-memory] there are
// typical datasheet figures, not measurements). SI units.
struct Preset {
  inertial::TriadSpec accel;
  inertial::TriadSpec gyro;
};

inertial::TriadSpec triad(double nd, double k, double b, double on, double sf, double mis,
                          double range, double lsb) {
  inertial::TriadSpec t;
  t.noise_density = nd;
  t.random_walk = k;
  t.bias_instability = b;
  t.turn_on_bias = on;
  t.scale_factor = sf;
  t.misalignment_rad = mis;
  t.range = range;
  t.resolution = lsb;
  return t;
}

Preset preset(ImuPreset name) {
  switch (name) {
    case ImuPreset::kConsumer:  // Bosch BMI088 class: ±24 g, ±2000 °/s, 16 bit
      return {
          triad(1.7e-3, 1.0e-4, 3.0e-4, 0.02, 2e-3, 1e-3, 24 * kG, 48 * kG / 65536),
          triad(2.4e-4, 2.0e-5, 9.7e-6, 0.5 * kDeg, 2e-3, 1e-3, 2000 * kDeg, 4000 * kDeg / 65536)};
    case ImuPreset::kIndustrial:  // ADIS16465-1 class: ±8 g, ±125 °/s, 32-bit output
      return {triad(2.0e-4, 1.0e-5, 3.5e-5, 2e-3, 5e-4, 2e-4, 8 * kG, 0.0),
              triad(4.4e-5, 1.0e-6, 9.7e-6, 0.1 * kDeg, 5e-4, 2e-4, 125 * kDeg, 0.0)};
    case ImuPreset::kTactical:  // Sensonor STIM300 class: ±10 g, ±400 °/s
      return {triad(1.2e-3, 5.0e-5, 4.9e-4, 7.4e-3, 3e-4, 1e-4, 10 * kG, 0.0),
              triad(4.4e-5, 2.0e-7, 2.4e-6, 4.0 * kDeg / 3600, 3e-4, 1e-4, 400 * kDeg, 0.0)};
    case ImuPreset::kIdeal:
    case ImuPreset::kCustom:
      break;
  }
  return {};
}

// What a row of imu.csv holds: the mean over the period that ends at its time (what an IMU's
// anti-alias filter and decimation deliver; integrates exactly), or the value at that instant.
enum class ImuSampling { kIntervalMean, kInstantaneous };
constexpr EnumName<ImuSampling> kImuSamplingNames[] = {
    {ImuSampling::kIntervalMean, "interval_mean"}, {ImuSampling::kInstantaneous, "instantaneous"}};
constexpr std::span<const EnumName<ImuSampling>> enumNames(ImuSampling) {
  return kImuSamplingNames;
}

struct MagnetometerConfig {
  bool enabled = true;
  double noise_density_t_rthz = 1e-8;
  double hard_iron_t = 2e-6;
  double soft_iron = 0.02;
  double resolution_t = 0.0;
};

struct TemperatureConfig {
  double reference_c = 25.0;
  double start_c = 25.0;
  double rate_c_s = 0.0;
};

// sensors.imus[]
struct ImuConfig {
  SensorBasics basics{"imu", 10'000'000, {}};
  ImuPreset preset = ImuPreset::kIndustrial;
  ImuSampling sampling = ImuSampling::kIntervalMean;
  bool increments = false;
  bool earth_rotation = true;
  inertial::TriadSpec accelerometer, gyroscope;  // preset "custom"
  MagnetometerConfig magnetometer;
  TemperatureConfig temperature;

  inertial::TriadSpec triad(bool gyro) const {
    if (preset == ImuPreset::kCustom)
      return gyro ? gyroscope : accelerometer;
    const Preset p = trainsim::sim::preset(preset);
    return gyro ? p.gyro : p.accel;
  }
  // The magnetometer's error terms: none for the ideal preset, which is ideal for every triad.
  MagnetometerConfig magnetometerErrors() const {
    if (preset != ImuPreset::kIdeal)
      return magnetometer;
    MagnetometerConfig m;
    m.enabled = magnetometer.enabled;
    m.noise_density_t_rthz = m.hard_iron_t = m.soft_iron = m.resolution_t = 0.0;
    return m;
  }
};

// The custom error terms of a triad; `u` is its unit in keys ("m_s2", "rad_s"). Every term has
// a maximum well beyond any real sensor's (consumer MEMS: about 2e-3 m/s^2/sqrt(Hz) and
// 2e-4 rad/s/sqrt(Hz)), so that no value can push a reading out of double's range.
scenario::Binding<inertial::TriadSpec> triadBinding(const std::string& u, bool gyro) {
  using T = inertial::TriadSpec;
  scenario::Binding<T> b;
  // An accelerometer's limits in m/s^2, a gyroscope's a tenth of them in rad/s.
  const double k = gyro ? 0.1 : 1.0;
  const auto add = [&](const std::string& key, double T::*m, const std::string& unit,
                       const std::string& description, double maximum,
                       scenario::Unit conversion = units::kNone,
                       std::optional<scenario::Sentinel> sentinel = std::nullopt) {
    scenario::Param& p = b.number(key, m, conversion, description, sentinel);
    p.unit = unit;
    p.range(0, maximum);
    return &p;
  };
  add("noise_density_" + u + "_rthz", &T::noise_density, u + "/sqrt(Hz)", "White noise density N",
      k);
  add("random_walk_" + u + "_rts", &T::random_walk, u + "/sqrt(s)", "Rate random walk K", k);
  add("bias_instability_" + u, &T::bias_instability, u, "Bias instability B (Allan floor 0.664 B)",
      k);
  add("bias_instability_tau_s", &T::bias_instability_tau_s, "s",
      "Cluster time tau0 of the flicker floor: Allan deviation 0.664 B at tau0, flat within "
      "2.5 % from tau0/100 to 1000 tau0, falling off as sqrt(tau) below and as 1/sqrt(tau) far "
      "above (eight Gauss-Markov terms, one decade apart)",
      1e6)
      ->range(0.01, 1e6);
  add("turn_on_bias_" + u, &T::turn_on_bias, u, "1-sigma per-run constant bias", 10 * k);
  add("scale_factor_ppm", &T::scale_factor, "ppm", "1-sigma per-run scale-factor error", 1e5,
      units::kPpm);
  add("misalignment_mrad", &T::misalignment_rad, "mrad", "1-sigma per-run cross-axis coupling", 100,
      units::kMilliradian);
  add("range_" + u, &T::range, u, "Saturation at +-range; 0: none", 2000 * k, units::kNone,
      scenario::Sentinel{0.0, std::numeric_limits<double>::infinity()});
  add("resolution_" + u, &T::resolution, u, "Quantization step (LSB); 0: none", k);
  add("temperature_coefficient_" + u + "_k", &T::temperature_coefficient, u + "/K",
      "Bias per kelvin", 0.1 * k);
  if (gyro)
    add("g_sensitivity_rad_s_per_m_s2", &T::g_sensitivity, "(rad/s)/(m/s^2)",
        "1-sigma of each g-sensitivity term", 0.01);
  return b;
}

const scenario::Binding<ImuConfig>& imuBinding() {
  static const scenario::Binding<inertial::TriadSpec> accel = triadBinding("m_s2", false),
                                                      gyro = triadBinding("rad_s", true);
  static const scenario::Binding<MagnetometerConfig> magnetometer = [] {
    using M = MagnetometerConfig;
    scenario::Binding<M> b;
    b.boolean("enabled", &M::enabled, "Write the magnetometer columns (else zeros)");
    b.number("noise_density_t_rthz", &M::noise_density_t_rthz, units::si("T/sqrt(Hz)"),
             "White noise density")
        .range(0, 1e-3);
    b.number("hard_iron_t", &M::hard_iron_t, units::si("T"), "1-sigma per-run hard-iron offset")
        .range(0, 1e-3);
    b.number("soft_iron", &M::soft_iron, units::kNone, "1-sigma per-run soft-iron matrix deviation")
        .range(0, 1);
    b.number("resolution_t", &M::resolution_t, units::si("T"), "Quantization step; 0: none")
        .range(0, 1e-4);
    return b;
  }();
  static const scenario::Binding<TemperatureConfig> temperature = [] {
    using T = TemperatureConfig;
    scenario::Binding<T> b;
    const scenario::Unit c = units::si("degC");
    b.number("reference_c", &T::reference_c, c, "Calibration temperature").range(-60, 120);
    b.number("start_c", &T::start_c, c, "Temperature at t = 0").range(-60, 120);
    b.number("rate_c_s", &T::rate_c_s, units::si("degC/s"), "Temperature ramp").range(-1, 1);
    return b;
  }();
  static const scenario::Binding<ImuConfig> binding = [] {
    scenario::Binding<ImuConfig> b;
    b.embed(&ImuConfig::basics,
            sensorBasics({"<name>.csv and <name>_truth.csv", 100'000, 1'000'000'000,
                          "Output period (100 Hz by default)", "Pose of the sensor's axes"}));
    b.choice("preset", &ImuConfig::preset,
             "Error model: a datasheet class (ADIS16465, BMI088, STIM300), ideal (no error on "
             "any triad, the magnetometer included), or custom (the accelerometer/gyroscope "
             "fields below)");
    b.choice("sampling", &ImuConfig::sampling,
             "What a row holds: interval_mean, the mean specific force, rate and field over the "
             "period ending at t_ns (an IMU's anti-alias filter and decimation; integrates back "
             "to the trajectory); instantaneous, the values at t_ns (a step in a rate between "
             "samples is then lost to an integrator)");
    b.boolean("increments", &ImuConfig::increments,
              "Also write the velocity and angle increments over each period (dv_*, dtheta_*: "
              "exact, with their coning and sculling parts, resolved in the sensor axes at the "
              "period's start; the error chain adds the period times the mean's error)");
    b.boolean("earth_rotation", &ImuConfig::earth_rotation,
              "Rotating WGS-84 Earth (normal gravity at each position, Earth rate); false: flat, "
              "non-rotating Earth with the anchor's gravity");
    b.object("accelerometer", &ImuConfig::accelerometer, accel,
             "Accelerometer error terms (used when preset is \"custom\")");
    b.object("gyroscope", &ImuConfig::gyroscope, gyro,
             "Gyroscope error terms (used when preset is \"custom\")");
    b.object("magnetometer", &ImuConfig::magnetometer, magnetometer,
             "Magnetometer on a dipole Earth field, with hard and soft iron");
    b.object("temperature", &ImuConfig::temperature, temperature,
             "Sensor temperature: start + rate * t, bias per kelvin from reference");
    return b;
  }();
  return binding;
}

// What render() computes for one reading: the truth at the sensor (pure in the trajectory),
// as a mean over the period or at the instant, and the increments over the period.
struct ImuTruthReading {
  TimeNs t_ns = 0;
  inertial::ImuTruth truth;
  Eigen::Vector3d field = Eigen::Vector3d::Zero();  // sensor axes, before hard and soft iron
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();     // sensor axes at the period's start
  Eigen::Vector3d dtheta = Eigen::Vector3d::Zero();
};

// The truth at one instant, with the sensor's attitude and velocity in the world frame.
struct ImuInstant {
  inertial::ImuTruth truth;
  Eigen::Vector3d field;
  Eigen::Quaterniond q_world_sensor;
  Eigen::Vector3d v_world;
  Eigen::Vector3d a_world;
};

class ImuSensor final : public SensorOf<ImuTruthReading> {
 public:
  explicit ImuSensor(const SensorSetup& setup)
      : ImuSensor(setup, imuBinding().read(setup.config)) {}
  ImuSensor(const SensorSetup& setup, const ImuConfig& c)
      : trajectory_(setup.context.trajectory),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        mount_(c.basics.mount.mount()),
        earth_(setup.context.anchor.origin(), c.earth_rotation),
        gravity_([this] { return inertial::LocalGravity(earth_); }),
        field_model_(setup.context.anchor),
        accel_(c.triad(false), RandomStream(setup.context.scenario.seed(), name_ + ".accel"),
               toSeconds(period_)),
        gyro_(c.triad(true), RandomStream(setup.context.scenario.seed(), name_ + ".gyro"),
              toSeconds(period_)),
        mag_(magSpec(c.magnetometerErrors()),
             RandomStream(setup.context.scenario.seed(), name_ + ".mag"), toSeconds(period_)),
        mag_on_(c.magnetometer.enabled),
        sampling_(c.sampling),
        increments_(c.increments),
        t_start_(c.temperature.start_c - c.temperature.reference_c),
        t_rate_(c.temperature.rate_c_s) {
    // Hard and soft iron: per-run draws.
    const RandomStream iron(setup.context.scenario.seed(), name_ + ".mag.iron");
    const auto a = iron.normal4(0), b = iron.normal4(1), c4 = iron.normal4(2);
    const double hard = c.magnetometerErrors().hard_iron_t;
    const double soft = c.magnetometerErrors().soft_iron;
    hard_iron_ = hard * Eigen::Vector3d(a[0], a[1], a[2]);
    soft_iron_ = Eigen::Matrix3d::Identity() +
                 soft * (Eigen::Matrix3d() << a[3], b[0], b[1], b[0], b[2], b[3], b[1], b[3], c4[0])
                            .finished();  // symmetric
  }

  static inertial::TriadSpec magSpec(const MagnetometerConfig& m) {
    inertial::TriadSpec t;
    t.noise_density = m.noise_density_t_rthz;
    t.resolution = m.resolution_t;
    return t;
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return kImuKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kImuCsvs, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    const std::vector<std::string> files = outputs();
    csv_ = &writer.appendFile(writer.layout().inSequence(files[0]));
    truth_ = &writer.appendFile(writer.layout().inSequence(files[1]));
    if (state.is_null()) {
      const std::string inc =
          increments_ ? ",dv_x_m_s,dv_y_m_s,dv_z_m_s,dtheta_x_rad,dtheta_y_rad,dtheta_z_rad" : "";
      csv_->write("t_ns,ax_m_s2,ay_m_s2,az_m_s2,wx_rad_s,wy_rad_s,wz_rad_s,mx_T,my_T,mz_T" + inc +
                  "\n");
      truth_->write(
          "t_ns,fx_m_s2,fy_m_s2,fz_m_s2,wx_rad_s,wy_rad_s,wz_rad_s,mx_T,my_T,mz_T,"
          "bias_ax_m_s2,bias_ay_m_s2,bias_az_m_s2,bias_wx_rad_s,bias_wy_rad_s,bias_wz_rad_s" +
          inc + "\n");
    } else {
      accel_.restore(state.at("accel"));
      gyro_.restore(state.at("gyro"));
      mag_.restore(state.at("mag"));
    }
  }

  nlohmann::json state() const override {
    return {{"accel", accel_.state()}, {"gyro", gyro_.state()}, {"mag", mag_.state()}};
  }

 private:
  ImuInstant instant(TimeNs t) const {
    const TrajectorySample s = trajectory_.at(t);
    const Eigen::Vector3d& r = mount_.position_m;
    const Eigen::Matrix3d r_wb = s.q_world_body.toRotationMatrix();
    inertial::MountKinematics m;
    m.p_world = s.p_world + r_wb * r;
    m.v_world = s.v_world + r_wb * s.w_body.cross(r);
    m.a_world = s.a_world + r_wb * (s.alpha_body.cross(r) + s.w_body.cross(s.w_body.cross(r)));
    m.r_world_sensor = r_wb * mount_.r_body_sensor;
    m.w_sensor = mount_.r_body_sensor.transpose() * s.w_body;
    return {inertial::imuTruth(earth_, m, gravity_.local().at(m.p_world)),
            m.r_world_sensor.transpose() * field_model_.at(m.p_world),
            Eigen::Quaterniond(m.r_world_sensor), m.v_world, m.a_world};
  }

  // The inertial attitude at t relative to the world frame at t = 0: the world turns with the
  // Earth, R_inertial_sensor(t) = exp(Ω t) R_world_sensor(t).
  Eigen::Quaterniond earthTurn(double seconds) const {
    const double rate = earth_.rate().norm();
    if (rate == 0.0)
      return Eigen::Quaterniond::Identity();
    return Eigen::Quaterniond(Eigen::AngleAxisd(rate * seconds, earth_.rate() / rate));
  }

  ImuTruthReading read(std::int64_t k) const override {
    ImuTruthReading out;
    out.t_ns = k * trajectory_.samplePeriod();
    const TimeNs t0 = out.t_ns - period_;
    std::optional<ImuInstant> now;  // at t_ns, evaluated once if needed
    const auto at_end = [&]() -> const ImuInstant& {
      if (!now)
        now = instant(out.t_ns);
      return *now;
    };
    if (sampling_ == ImuSampling::kInstantaneous) {
      out.truth = at_end().truth;
      out.field = at_end().field;
    }
    if (sampling_ == ImuSampling::kInstantaneous && !increments_)
      return out;
    // Quadrature over (t0, t1]: means, and Δv = ∫ R_is(t0)ᵀ R_is(t) f dt in the sensor axes
    // at t0. Before t = 0 the train stands where it starts (Trajectory::at clamps).
    const Eigen::Quaterniond q0 =
        increments_ ? instant(t0).q_world_sensor.conjugate() : Eigen::Quaterniond::Identity();
    inertial::ImuTruth sum;
    Eigen::Vector3d field = Eigen::Vector3d::Zero();
    intervalNodes(
        trajectory_, t0, out.t_ns,
        [&](TimeNs t, double w) {
          const ImuInstant at = instant(t);
          sum.specific_force += w * at.truth.specific_force;
          sum.angular_rate += w * at.truth.angular_rate;
          field += w * at.field;
          if (increments_)
            out.dv += w * (q0 * earthTurn(toSeconds(t - t0)) * at.q_world_sensor *
                           at.truth.specific_force);
        },
        [&](TimeNs t) {
          // Where the roll rate steps (ends of linear cant ramps) a sensor off the roll axis
          // steps in velocity: an impulse of specific force, which the mean must carry.
          const ImuInstant before = instant(t - 1), after = instant(t + 1);
          const Eigen::Vector3d jump =
              after.v_world - before.v_world - 1e-9 * (after.a_world + before.a_world);
          if (jump.squaredNorm() == 0.0)
            return;
          sum.specific_force += after.q_world_sensor.conjugate() * jump;
          if (increments_)
            out.dv += q0 * earthTurn(toSeconds(t - t0)) * jump;
        });
    const double period_s = toSeconds(period_);
    if (sampling_ == ImuSampling::kIntervalMean) {
      out.truth.specific_force = sum.specific_force / period_s;
      out.truth.angular_rate = sum.angular_rate / period_s;
      out.field = field / period_s;
    }
    if (increments_) {
      // Δθ: the rotation vector of R_is(t0)ᵀ R_is(t1), exact (coning included).
      const Eigen::Quaterniond q =
          (q0 * earthTurn(period_s) * at_end().q_world_sensor).normalized();
      const Eigen::AngleAxisd aa(q.w() < 0 ? Eigen::Quaterniond(-q.coeffs()) : q);
      out.dtheta = aa.angle() * aa.axis();
    }
    return out;
  }

  void write(std::int64_t, ImuTruthReading& r) override {
    const inertial::ImuTruth& truth = r.truth;
    const double temperature = t_start_ + t_rate_ * toSeconds(r.t_ns);
    // The error models count readings (their slow terms update every so many readings).
    const auto index = static_cast<std::uint64_t>(r.t_ns / period_);
    const Eigen::Vector3d a =
        accel_.measure(index, truth.specific_force, Eigen::Vector3d::Zero(), temperature);
    const Eigen::Vector3d w =
        gyro_.measure(index, truth.angular_rate, truth.specific_force, temperature);
    Eigen::Vector3d mag = Eigen::Vector3d::Zero();
    if (mag_on_)
      mag = mag_.measure(index, soft_iron_ * (r.field + hard_iron_));
    std::string row =
        fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", r.t_ns,
                    a.x(), a.y(), a.z(), w.x(), w.y(), w.z(), mag.x(), mag.y(), mag.z());
    const Eigen::Vector3d ba = accel_.bias(), bg = gyro_.bias();
    const Eigen::Vector3d& field = r.field;
    std::string truth_row = fmt::format(
        "{},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
        "{:.9g},{:.9g},{:.9g},{:.9g}",
        r.t_ns, truth.specific_force.x(), truth.specific_force.y(), truth.specific_force.z(),
        truth.angular_rate.x(), truth.angular_rate.y(), truth.angular_rate.z(), field.x(),
        field.y(), field.z(), ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z());
    if (increments_) {
      // The increments carry the same error as the means, over the period.
      const double period_s = toSeconds(period_);
      const Eigen::Vector3d dv = r.dv + period_s * (a - truth.specific_force);
      const Eigen::Vector3d dth = r.dtheta + period_s * (w - truth.angular_rate);
      fmt::format_to(std::back_inserter(row), ",{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}",
                     dv.x(), dv.y(), dv.z(), dth.x(), dth.y(), dth.z());
      fmt::format_to(std::back_inserter(truth_row),
                     ",{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}", r.dv.x(), r.dv.y(),
                     r.dv.z(), r.dtheta.x(), r.dtheta.y(), r.dtheta.z());
    }
    csv_->write(row + "\n");
    truth_->write(truth_row + "\n");
  }

  const Trajectory& trajectory_;
  std::string name_;
  TimeNs period_;
  Mount mount_;
  inertial::Earth earth_;
  // Gravity caches per rendering thread; each is a pure function of position.
  mutable tbb::enumerable_thread_specific<inertial::LocalGravity> gravity_;
  inertial::DipoleField field_model_;
  inertial::TriadErrorModel accel_, gyro_, mag_;
  bool mag_on_;
  ImuSampling sampling_;
  bool increments_;
  Eigen::Vector3d hard_iron_;
  Eigen::Matrix3d soft_iron_;
  double t_start_ = 0.0, t_rate_ = 0.0;
  io::AppendFile* csv_ = nullptr;
  io::AppendFile* truth_ = nullptr;
};

}  // namespace

scenario::Param declareImu() {
  return imuBinding().declare(
      "imu",
      "A 9-axis IMU on the carbody. Columns in the sensor's own axes; imu.csv is the "
      "measurement, <name>_truth.csv the true specific force, rate, field and biases.");
}

void checkImu(const scenario::Json& item, const std::string& path,
              std::vector<scenario::Problem>& problems) {
  imuBinding().problems(imuBinding().read(item), path, problems);
}

std::unique_ptr<Sensor> createImu(const SensorSetup& setup) {
  return std::make_unique<ImuSensor>(setup);
}

}  // namespace trainsim::sim
