#include "imu_sensor.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>

#include "trainsim/core/error.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/inertial/earth.hpp"
#include "trainsim/inertial/error_model.hpp"

namespace trainsim::sim {
namespace {

using scenario::Json;
using scenario::number;
using scenario::object;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kG = 9.80665;

// Datasheet-class presets (rail-imu-reference.md §2.4; values marked [std-memory] there are
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

class ImuSensor final : public Sensor {
 public:
  ImuSensor(const SensorSetup& setup)
      : name_(setup.config.at("name").get<std::string>()),
        period_(setup.config.at("period_ns").get<TimeNs>()),
        anchor_({setup.scenario.get<double>("geodetic_origin.latitude_deg"),
                 setup.scenario.get<double>("geodetic_origin.longitude_deg"),
                 setup.scenario.get<double>("geodetic_origin.height_m")}),
        earth_(anchor_.origin(), setup.config.at("earth_rotation").get<bool>()),
        accel_(spec(setup, "accelerometer"), RandomStream(setup.scenario.seed(), name_ + ".accel"),
               toSeconds(period_)),
        gyro_(spec(setup, "gyroscope"), RandomStream(setup.scenario.seed(), name_ + ".gyro"),
              toSeconds(period_)),
        mag_(magSpec(setup.config.at("magnetometer")),
             RandomStream(setup.scenario.seed(), name_ + ".mag"), toSeconds(period_)),
        mag_on_(setup.config.at("magnetometer").at("enabled").get<bool>()) {
    const Json& m = setup.config.at("mount");
    mount_ = {m.at("x_m").get<double>(), m.at("y_m").get<double>(), m.at("z_m").get<double>()};
    r_body_sensor_ =
        (Eigen::AngleAxisd(m.at("yaw_deg").get<double>() * kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(m.at("pitch_deg").get<double>() * kDeg, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(m.at("roll_deg").get<double>() * kDeg, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Json& t = setup.config.at("temperature");
    t_start_ = t.at("start_c").get<double>() - t.at("reference_c").get<double>();
    t_rate_ = t.at("rate_c_s").get<double>();
    // Hard and soft iron: per-run draws.
    const RandomStream iron(setup.scenario.seed(), name_ + ".mag.iron");
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
      throw ConfigError(
          fmt::format("sensors.imus[{}].preset: unknown preset '{}'", setup.index, name));
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

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    const auto dir = writer.sequenceDir().lexically_relative(writer.root());
    csv_ = &writer.appendFile(dir / (name_ + ".csv"));
    truth_ = &writer.appendFile(dir / (name_ + "_truth.csv"));
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

  void capture(std::int64_t, const TrajectorySample& s) override {
    const Eigen::Matrix3d r_wb = s.q_world_body.toRotationMatrix();
    const Eigen::Vector3d arm = r_wb * mount_;
    inertial::MountKinematics m;
    m.p_world = s.p_world + arm;
    m.v_world = s.v_world + r_wb * s.w_body.cross(mount_);
    m.a_world =
        s.a_world + r_wb * (s.alpha_body.cross(mount_) + s.w_body.cross(s.w_body.cross(mount_)));
    m.r_world_sensor = r_wb * r_body_sensor_;
    m.w_sensor = r_body_sensor_.transpose() * s.w_body;
    const inertial::ImuTruth truth = inertial::imuTruth(earth_, m, gravity_.at(m.p_world));
    const Eigen::Vector3d field = m.r_world_sensor.transpose() * field_model_.at(m.p_world);
    const double dt = toSeconds(s.t_ns);
    const double temperature = t_start_ + t_rate_ * dt;
    // The error models count readings (their slow terms update every so many readings).
    const auto index = static_cast<std::uint64_t>(s.t_ns / period_);
    const Eigen::Vector3d a = accel_.measure(index, truth.specific_force, {}, temperature);
    const Eigen::Vector3d w =
        gyro_.measure(index, truth.angular_rate, truth.specific_force, temperature);
    Eigen::Vector3d mag = Eigen::Vector3d::Zero();
    if (mag_on_)
      mag = mag_.measure(index, soft_iron_ * (field + hard_iron_));
    csv_->write(fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                            s.t_ns, a.x(), a.y(), a.z(), w.x(), w.y(), w.z(), mag.x(), mag.y(),
                            mag.z()));
    const Eigen::Vector3d ba = accel_.bias(), bg = gyro_.bias();
    truth_->write(fmt::format(
        "{},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
        "{:.9g},{:.9g},{:.9g},{:.9g}\n",
        s.t_ns, truth.specific_force.x(), truth.specific_force.y(), truth.specific_force.z(),
        truth.angular_rate.x(), truth.angular_rate.y(), truth.angular_rate.z(), field.x(),
        field.y(), field.z(), ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z()));
  }

  nlohmann::json state() const override {
    return {{"accel", accel_.state()}, {"gyro", gyro_.state()}, {"mag", mag_.state()}};
  }

 private:
  std::string name_;
  TimeNs period_;
  GeodeticAnchor anchor_;
  inertial::Earth earth_;
  inertial::LocalGravity gravity_{earth_};
  inertial::DipoleField field_model_{anchor_};
  inertial::TriadErrorModel accel_, gyro_, mag_;
  bool mag_on_;
  Eigen::Vector3d mount_;
  Eigen::Matrix3d r_body_sensor_;
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
      {scenario::string("name", "imu", "Sensor name: files <name>.csv and <name>_truth.csv"),
       scenario::integer("period_ns", 10'000'000, "ns", "Output period (100 Hz by default)")
           .range(100'000, 1'000'000'000)
           .multipleOf("trajectory.sample_period_ns"),
       object("mount", "Pose of the sensor relative to the body reference point (body axes)",
              {number("x_m", 0, "m", "Forward").range(-100, 100),
               number("y_m", 0, "m", "Left").range(-10, 10),
               number("z_m", 0, "m", "Up").range(-10, 10),
               number("roll_deg", 0, "deg", "Sensor roll about body x").range(-180, 180),
               number("pitch_deg", 0, "deg", "Sensor pitch about body y").range(-90, 90),
               number("yaw_deg", 0, "deg", "Sensor yaw about body z").range(-180, 180)}),
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
