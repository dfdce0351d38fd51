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

namespace trainsim::sim {
namespace {

using scenario::Json;
using scenario::number;
using scenario::object;

constexpr double kDeg = kRadPerDeg;
constexpr double kG = kStandardGravity_m_s2;

// Datasheet-class presets (docs/REFERENCES.md R2.4; values marked [std-memory] there are
// typical datasheet figures, not measurements). SI units.
struct Preset {
  const char* name;
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

std::optional<Preset> preset(const std::string& name) {
  if (name == "consumer")  // Bosch BMI088 class: ±24 g, ±2000 °/s, 16 bit
    return Preset{
        "consumer", triad(1.7e-3, 1.0e-4, 3.0e-4, 0.02, 2e-3, 1e-3, 24 * kG, 48 * kG / 65536),
        triad(2.4e-4, 2.0e-5, 9.7e-6, 0.5 * kDeg, 2e-3, 1e-3, 2000 * kDeg, 4000 * kDeg / 65536)};
  if (name == "industrial")  // ADIS16465-1 class: ±8 g, ±125 °/s, 32-bit output
    return Preset{"industrial", triad(2.0e-4, 1.0e-5, 3.5e-5, 2e-3, 5e-4, 2e-4, 8 * kG, 0.0),
                  triad(4.4e-5, 1.0e-6, 9.7e-6, 0.1 * kDeg, 5e-4, 2e-4, 125 * kDeg, 0.0)};
  if (name == "tactical")  // Sensonor STIM300 class: ±10 g, ±400 °/s
    return Preset{"tactical", triad(1.2e-3, 5.0e-5, 4.9e-4, 7.4e-3, 3e-4, 1e-4, 10 * kG, 0.0),
                  triad(4.4e-5, 2.0e-7, 2.4e-6, 4.0 * kDeg / 3600, 3e-4, 1e-4, 400 * kDeg, 0.0)};
  if (name == "ideal")
    return Preset{"ideal", {}, {}};
  return std::nullopt;
}

scenario::Param triadParams(const std::string& key, const std::string& what, const std::string& u,
                            bool gyro) {
  std::vector<scenario::Param> f = {
      number("noise_density_" + u + "_rthz", 0, u + "/sqrt(Hz)", "White noise density N"),
      number("random_walk_" + u + "_rts", 0, u + "/sqrt(s)", "Rate random walk K"),
      number("bias_instability_" + u, 0, u, "Bias instability B (Allan floor 0.664 B)"),
      number("bias_instability_tau_s", 100, "s", "Cluster time at the middle of the floor")
          .range(0.01, 1e6),
      number("turn_on_bias_" + u, 0, u, "1-sigma per-run constant bias"),
      number("scale_factor_ppm", 0, "ppm", "1-sigma per-run scale-factor error"),
      number("misalignment_mrad", 0, "mrad", "1-sigma per-run cross-axis coupling"),
      number("range_" + u, 0, u, "Saturation at +-range; 0: none"),
      number("resolution_" + u, 0, u, "Quantization step (LSB); 0: none"),
      number("temperature_coefficient_" + u + "_k", 0, u + "/K", "Bias per kelvin")};
  if (gyro)
    f.push_back(number("g_sensitivity_rad_s_per_m_s2", 0, "(rad/s)/(m/s^2)",
                       "1-sigma of each g-sensitivity term"));
  for (auto& p : f)
    if (!p.minimum)
      p.range(0, std::nullopt);
  return object(key, what + " error terms (used when preset is \"custom\")", std::move(f));
}

inertial::TriadSpec customTriad(const Json& c, const std::string& u, bool gyro) {
  inertial::TriadSpec t;
  t.noise_density = c.at("noise_density_" + u + "_rthz").get<double>();
  t.random_walk = c.at("random_walk_" + u + "_rts").get<double>();
  t.bias_instability = c.at("bias_instability_" + u).get<double>();
  t.bias_instability_tau_s = c.at("bias_instability_tau_s").get<double>();
  t.turn_on_bias = c.at("turn_on_bias_" + u).get<double>();
  t.scale_factor = c.at("scale_factor_ppm").get<double>() * 1e-6;
  t.misalignment_rad = c.at("misalignment_mrad").get<double>() * 1e-3;
  const double range = c.at("range_" + u).get<double>();
  t.range = range > 0 ? range : std::numeric_limits<double>::infinity();
  t.resolution = c.at("resolution_" + u).get<double>();
  t.temperature_coefficient = c.at("temperature_coefficient_" + u + "_k").get<double>();
  if (gyro)
    t.g_sensitivity = c.at("g_sensitivity_rad_s_per_m_s2").get<double>();
  return t;
}

// What render() computes for one reading: the truth at the sensor (pure in the trajectory).
struct ImuTruthReading {
  TimeNs t_ns = 0;
  inertial::ImuTruth truth;
  Eigen::Vector3d field = Eigen::Vector3d::Zero();  // sensor axes, before hard and soft iron
};

class ImuSensor final : public SensorOf<ImuTruthReading> {
 public:
  explicit ImuSensor(const SensorSetup& setup)
      : trajectory_(setup.context.trajectory),
        name_(readSensorName(setup.config)),
        period_(readPeriod(setup.config)),
        mount_(readMount(setup.config)),
        earth_(setup.context.anchor.origin(), setup.config.at("earth_rotation").get<bool>()),
        gravity_([this] { return inertial::LocalGravity(earth_); }),
        field_model_(setup.context.anchor),
        accel_(spec(setup, "accelerometer"),
               RandomStream(setup.context.scenario.seed(), name_ + ".accel"), toSeconds(period_)),
        gyro_(spec(setup, "gyroscope"),
              RandomStream(setup.context.scenario.seed(), name_ + ".gyro"), toSeconds(period_)),
        mag_(magSpec(setup.config.at("magnetometer")),
             RandomStream(setup.context.scenario.seed(), name_ + ".mag"), toSeconds(period_)),
        mag_on_(setup.config.at("magnetometer").at("enabled").get<bool>()) {
    const Json& t = setup.config.at("temperature");
    t_start_ = t.at("start_c").get<double>() - t.at("reference_c").get<double>();
    t_rate_ = t.at("rate_c_s").get<double>();
    // Hard and soft iron: per-run draws.
    const RandomStream iron(setup.context.scenario.seed(), name_ + ".mag.iron");
    const auto a = iron.normal4(0), b = iron.normal4(1), c = iron.normal4(2);
    const double hard = setup.config.at("magnetometer").at("hard_iron_t").get<double>();
    const double soft = setup.config.at("magnetometer").at("soft_iron").get<double>();
    hard_iron_ = hard * Eigen::Vector3d(a[0], a[1], a[2]);
    soft_iron_ = Eigen::Matrix3d::Identity() +
                 soft * (Eigen::Matrix3d() << a[3], b[0], b[1], b[0], b[2], b[3], b[1], b[3], c[0])
                            .finished();  // symmetric
  }

  static inertial::TriadSpec spec(const SensorSetup& setup, const std::string& which) {
    const std::string name = setup.config.at("preset").get<std::string>();
    const bool gyro = which == "gyroscope";
    if (name == "custom")
      return customTriad(setup.config.at(which), gyro ? "rad_s" : "m_s2", gyro);
    const auto p = preset(name);
    if (!p)
      throw ConfigError(fmt::format("{}.preset: unknown preset '{}'", setup.path, name));
    return gyro ? p->gyro : p->accel;
  }
  static inertial::TriadSpec magSpec(const Json& m) {
    inertial::TriadSpec t;
    t.noise_density = m.at("noise_density_t_rthz").get<double>();
    t.resolution = m.at("resolution_t").get<double>();
    return t;
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return "imu"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kImuCsvs, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    const auto dir = writer.sequenceDir().lexically_relative(writer.root());
    const std::vector<std::string> files = outputs();
    csv_ = &writer.appendFile(dir / files[0]);
    truth_ = &writer.appendFile(dir / files[1]);
    if (state.is_null()) {
      csv_->write("t_ns,ax_m_s2,ay_m_s2,az_m_s2,wx_rad_s,wy_rad_s,wz_rad_s,mx_T,my_T,mz_T\n");
      truth_->write(
          "t_ns,fx_m_s2,fy_m_s2,fz_m_s2,wx_rad_s,wy_rad_s,wz_rad_s,mx_T,my_T,mz_T,"
          "bias_ax_m_s2,bias_ay_m_s2,bias_az_m_s2,bias_wx_rad_s,bias_wy_rad_s,bias_wz_rad_s\n");
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
  ImuTruthReading read(std::int64_t k) const override {
    const TrajectorySample s = trajectory_.sample(k);
    const Eigen::Vector3d& r = mount_.position_m;
    const Eigen::Matrix3d r_wb = s.q_world_body.toRotationMatrix();
    inertial::MountKinematics m;
    m.p_world = s.p_world + r_wb * r;
    m.v_world = s.v_world + r_wb * s.w_body.cross(r);
    m.a_world = s.a_world + r_wb * (s.alpha_body.cross(r) + s.w_body.cross(s.w_body.cross(r)));
    m.r_world_sensor = r_wb * mount_.r_body_sensor;
    m.w_sensor = mount_.r_body_sensor.transpose() * s.w_body;
    ImuTruthReading out;
    out.t_ns = s.t_ns;
    out.truth = inertial::imuTruth(earth_, m, gravity_.local().at(m.p_world));
    out.field = m.r_world_sensor.transpose() * field_model_.at(m.p_world);
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
    csv_->write(fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                            r.t_ns, a.x(), a.y(), a.z(), w.x(), w.y(), w.z(), mag.x(), mag.y(),
                            mag.z()));
    const Eigen::Vector3d ba = accel_.bias(), bg = gyro_.bias();
    const Eigen::Vector3d& field = r.field;
    truth_->write(fmt::format(
        "{},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
        "{:.9g},{:.9g},{:.9g},{:.9g}\n",
        r.t_ns, truth.specific_force.x(), truth.specific_force.y(), truth.specific_force.z(),
        truth.angular_rate.x(), truth.angular_rate.y(), truth.angular_rate.z(), field.x(),
        field.y(), field.z(), ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z()));
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
  Eigen::Vector3d hard_iron_;
  Eigen::Matrix3d soft_iron_;
  double t_start_ = 0.0, t_rate_ = 0.0;
  io::AppendFile* csv_ = nullptr;
  io::AppendFile* truth_ = nullptr;
};

}  // namespace

scenario::Param declareImu() {
  return object(
      "imu",
      "A 9-axis IMU on the carbody. Columns in the sensor's own axes; imu.csv is the "
      "measurement, <name>_truth.csv the true specific force, rate, field and biases.",
      {declareSensorName("imu", "<name>.csv and <name>_truth.csv"),
       declarePeriod(10'000'000, 100'000, 1'000'000'000, "Output period (100 Hz by default)"),
       declareMount("Pose of the sensor's axes"),
       scenario::choice("preset", "industrial",
                        {"industrial", "consumer", "tactical", "ideal", "custom"},
                        "Error model: a datasheet class (ADIS16465, BMI088, STIM300), ideal "
                        "(noise-free), or custom (the accelerometer/gyroscope fields below)"),
       scenario::boolean("earth_rotation", true,
                         "Rotating WGS-84 Earth (normal gravity at each position, Earth rate); "
                         "false: flat, non-rotating Earth with the anchor's gravity"),
       triadParams("accelerometer", "Accelerometer", "m_s2", false),
       triadParams("gyroscope", "Gyroscope", "rad_s", true),
       object(
           "magnetometer", "Magnetometer on a dipole Earth field, with hard and soft iron",
           {scenario::boolean("enabled", true, "Write the magnetometer columns (else zeros)"),
            number("noise_density_t_rthz", 1e-8, "T/sqrt(Hz)", "White noise density")
                .range(0, 1e-3),
            number("hard_iron_t", 2e-6, "T", "1-sigma per-run hard-iron offset").range(0, 1e-3),
            number("soft_iron", 0.02, "", "1-sigma per-run soft-iron matrix deviation").range(0, 1),
            number("resolution_t", 0, "T", "Quantization step; 0: none").range(0, 1e-4)}),
       object("temperature", "Sensor temperature: start + rate * t, bias per kelvin from reference",
              {number("reference_c", 25, "degC", "Calibration temperature").range(-60, 120),
               number("start_c", 25, "degC", "Temperature at t = 0").range(-60, 120),
               number("rate_c_s", 0, "degC/s", "Temperature ramp").range(-1, 1)})});
}

std::unique_ptr<Sensor> createImu(const SensorSetup& setup) {
  return std::make_unique<ImuSensor>(setup);
}

}  // namespace trainsim::sim
