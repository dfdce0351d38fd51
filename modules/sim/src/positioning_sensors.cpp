#include "positioning_sensors.hpp"

#include <fmt/format.h>

#include "trainsim/core/error.hpp"
#include "trainsim/positioning/balise.hpp"
#include "trainsim/positioning/gnss.hpp"
#include "trainsim/positioning/odometer.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

using scenario::Json;

// Thin adapters: the physics is in modules/positioning; these read the scenario, take the
// truth from the trajectory in render() and run the models and write CSV rows in commit().

// A sensor's readings file: <name>.csv in the sequence folder.
std::filesystem::path sequenceFile(io::DatasetWriter& writer, const std::string& name) {
  return writer.layout().inSequence(sensorFiles(kReadingsCsv, name).front());
}

const track::Route& requireRoute(const SensorSetup& setup) {
  if (setup.context.route == nullptr)
    throw RuntimeError(fmt::format("{}: this sensor needs the planned route", setup.path));
  return *setup.context.route;
}

constexpr TimeNs kMinPeriod = 100'000, kMaxPeriod = 60'000'000'000;
constexpr scenario::Unit kM = scenario::units::si("m");
constexpr scenario::Unit kS = scenario::units::si("s");
constexpr scenario::Unit kMPerS = scenario::units::si("m/s");
constexpr scenario::Unit kNone = scenario::units::kNone;

// sensors.gnss_receivers[]
struct GnssConfig {
  SensorBasics basics{"gnss", 1'000'000'000, {Eigen::Vector3d(0.0, 0.0, 4.0)}};
  positioning::GnssErrorSpec errors;
  double reacquisition_s = 5.0;
};

const scenario::Binding<GnssConfig>& gnssBinding() {
  static const scenario::Binding<GnssConfig> binding = [] {
    using E = positioning::GnssErrorSpec;
    scenario::Binding<GnssConfig> b;
    b.embed(&GnssConfig::basics,
            sensorBasics({"<name>.csv", kMinPeriod, kMaxPeriod, "Fix period (1 Hz by default)",
                          "Antenna phase centre (its attitude does not matter)"}));
    const auto error = [](double E::*m) { return scenario::nested(&GnssConfig::errors, m); };
    b.number("horizontal_sigma_m", error(&E::horizontal_sigma_m), kM,
             "Gauss-Markov horizontal error, 1 sigma per axis")
        .range(0, 1000);
    b.number("vertical_sigma_m", error(&E::vertical_sigma_m), kM,
             "Gauss-Markov vertical error, 1 sigma")
        .range(0, 1000);
    b.number("correlation_time_s", error(&E::correlation_time_s), kS,
             "Correlation time of the Gauss-Markov error")
        .range(0.1, 1e5);
    b.number("white_sigma_m", error(&E::white_sigma_m), kM,
             "White position noise, 1 sigma per axis")
        .range(0, 100);
    b.number("velocity_sigma_m_s", error(&E::velocity_sigma_m_s), kMPerS,
             "White velocity noise, 1 sigma per axis")
        .range(0, 10);
    b.number("velocity_gm_sigma_m_s", error(&E::velocity_gm_sigma_m_s), kMPerS,
             "Gauss-Markov velocity error (same correlation time), 1 sigma per axis")
        .range(0, 10);
    b.number("reacquisition_s", &GnssConfig::reacquisition_s, kS,
             "No fix for this long after the antenna leaves a tunnel (timed from the exit)")
        .range(0, 600);
    return b;
  }();
  return binding;
}

// sensors.odometers[]: every axle of the rigid train runs the same distance, so the odometer
// has no mount.
struct OdometerConfig {
  SensorBasics basics{"odometer", 10'000'000, {}};
  positioning::OdometerSpec spec;
};

const scenario::Binding<positioning::OdometerSpec::Slip>& slipBinding() {
  static const scenario::Binding<positioning::OdometerSpec::Slip> binding = [] {
    using S = positioning::OdometerSpec::Slip;
    scenario::Binding<S> b;
    b.boolean("enabled", &S::enabled, "Simulate slip and slide");
    b.number("accel_threshold_m_s2", &S::accel_threshold_m_s2, scenario::units::si("m/s^2"),
             "Slip only above this acceleration")
        .range(0, 10);
    b.number("brake_threshold_m_s2", &S::brake_threshold_m_s2, scenario::units::si("m/s^2"),
             "Slide only above this braking")
        .range(0, 10);
    b.number("rate_per_s", &S::rate_per_s, scenario::units::si("1/s"),
             "Episode start rate while above threshold")
        .range(0, 100);
    b.number("duration_min_s", &S::duration_min_s, kS, "Shortest episode").range(0.01, 600);
    b.number("duration_max_s", &S::duration_max_s, kS, "Longest episode").range(0.01, 600);
    b.number("magnitude_max", &S::magnitude_max, kNone,
             "Largest relative speed error of an episode")
        .range(0.02, 0.9);
    b.notAbove(&S::duration_min_s, &S::duration_max_s);
    return b;
  }();
  return binding;
}

const scenario::Binding<OdometerConfig>& odometerBinding() {
  static const scenario::Binding<OdometerConfig> binding = [] {
    using O = positioning::OdometerSpec;
    scenario::Binding<OdometerConfig> b;
    b.embed(&OdometerConfig::basics, sensorBasics({"<name>.csv", kMinPeriod, kMaxPeriod,
                                                   "Output period (100 Hz by default)", nullptr}));
    b.number("wheel_diameter_m", scenario::nested(&OdometerConfig::spec, &O::wheel_diameter_m), kM,
             "Nominal wheel diameter")
        .range(0.3, 2.0);
    b.integer("pulses_per_revolution",
              scenario::nested(&OdometerConfig::spec, &O::pulses_per_revolution), "",
              "Encoder pulses per wheel turn")
        .range(1, 100000);
    b.number(
         "scale_error", scenario::nested(&OdometerConfig::spec, &O::scale_error), kNone,
         "Distance scale error: the encoder reads (1 + e) times the distance travelled (worn or "
         "mis-calibrated wheel)")
        .range(-0.2, 0.2);
    b.object("slip", scenario::nested(&OdometerConfig::spec, &O::slip), slipBinding(),
             "Wheel slip (traction) and slide (braking) episodes");
    return b;
  }();
  return binding;
}

// sensors.balise_readers[]
struct BaliseReaderConfig {
  SensorBasics basics{"balises", 10'000'000, {Eigen::Vector3d(10.75, 0.0, -0.5)}};
  positioning::BalisePlacement placement;
  double location_accuracy_m = 1.0;
  double detection_sigma_m = 0.3;
};

const scenario::Binding<BaliseReaderConfig>& baliseReaderBinding() {
  static const scenario::Binding<BaliseReaderConfig> binding = [] {
    using P = positioning::BalisePlacement;
    using C = BaliseReaderConfig;
    scenario::Binding<C> b;
    b.embed(&C::basics,
            sensorBasics({"<name>.csv", kMinPeriod, kMaxPeriod,
                          "Reader polling period (events carry their own time)",
                          "Reader antenna under the carbody; a balise is read when the antenna's "
                          "x passes it (2 m ahead of the front bogie pivot by default)"}));
    const auto place = [](auto P::*m) { return scenario::nested(&C::placement, m); };
    b.number("first_group_m", place(&P::first_group_m), kM,
             "Distance of the first group from the route start")
        .range(0, 1e7);
    b.number("group_spacing_m", place(&P::group_spacing_m), kM, "Distance between balise groups")
        .range(10, 1e6);
    b.integer("balises_per_group", place(&P::balises_per_group), "", "Balises in a group")
        .range(1, 8);
    b.number("balise_spacing_m", place(&P::balise_spacing_m), kM,
             "Distance between balises of a group")
        .range(0.5, 20);
    b.number("station_approach_m", place(&P::station_approach_m), kM,
             "Extra group this far before each station; 0: none")
        .range(0, 5000);
    b.number("location_accuracy_m", &C::location_accuracy_m, kM,
             "Group location accuracy (ETCS Q_LOCACC)")
        .range(0, 63);
    b.number("detection_sigma_m", &C::detection_sigma_m, kM,
             "Where the reader detects the balise, 1 sigma")
        .range(0, 5);
    return b;
  }();
  return binding;
}

// ---------------------------------------------------------------------------------------
// GNSS receiver: the antenna's true position and velocity and whether it has a fix (render,
// pure in the trajectory), the error model (commit).

struct AntennaTruth {
  TimeNs t_ns = 0;
  Eigen::Vector3d p_world, v_world;
  bool fix = false;  // outside tunnels and past the reacquisition delay
};

class GnssSensor final : public SensorOf<AntennaTruth> {
 public:
  explicit GnssSensor(const SensorSetup& setup)
      : GnssSensor(setup, gnssBinding().read(setup.config)) {}
  GnssSensor(const SensorSetup& setup, const GnssConfig& c)
      : trajectory_(setup.context.trajectory),
        anchor_(setup.context.anchor),
        route_(requireRoute(setup)),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        mount_(c.basics.mount.mount()),
        ahead_of_front_(aheadOfFrontPivot(setup.context.scenario.json(), mount_)),
        errors_(c.errors, period_, RandomStream(setup.context.scenario.seed(), name_ + ".gnss")),
        visibility_(tunnels(route_), fromSeconds(c.reacquisition_s)) {}

  std::string name() const override { return name_; }
  std::string kind() const override { return kGnssKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kReadingsCsv, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null()) {
      csv_->write("t_ns,fix,latitude_deg,longitude_deg,height_m,ve_m_s,vn_m_s,vu_m_s\n");
    } else {
      errors_.restore(state.at("errors"));
    }
  }

  nlohmann::json state() const override { return {{"errors", errors_.state()}}; }

 private:
  static std::vector<std::pair<double, double>> tunnels(const track::Route& route) {
    std::vector<std::pair<double, double>> out;
    for (const track::Block& b : route.blocks)
      if (b.type == track::BlockType::kTunnel)
        out.emplace_back(b.chainage_begin_m, b.chainage_end_m);
    return out;
  }

  AntennaTruth read(std::int64_t k) const override {
    const TrajectorySample s = trajectory_.sample(k);
    const Eigen::Matrix3d r = s.q_world_body.toRotationMatrix();
    const Eigen::Vector3d& arm = mount_.position_m;
    const auto antenna_chainage = [&](TimeNs t) {
      return (t == s.t_ns ? s : trajectory_.at(t)).chainage_m + ahead_of_front_;
    };
    return {s.t_ns, s.p_world + r * arm, s.v_world + r * s.w_body.cross(arm),
            visibility_.fix(s.t_ns, antenna_chainage)};
  }

  void write(std::int64_t k, AntennaTruth& a) override {
    const positioning::GnssErrors e = errors_.step(static_cast<std::uint64_t>(k));
    if (!a.fix) {
      csv_->write(fmt::format("{},0,,,,,,\n", a.t_ns));
      return;
    }
    // Errors are east/north/up at the antenna; the anchor frame's axes differ from the local
    // ones by the angle subtended at the Earth's centre, which rotateAnchorFromLocalEnu gives.
    const Eigen::Matrix3d r_anchor_local = anchor_.rotationAnchorFromLocalEnu(a.p_world);
    const GeodeticPoint g = anchor_.fromEnu(a.p_world + r_anchor_local * e.position_m);
    const Eigen::Vector3d v = r_anchor_local.transpose() * a.v_world + e.velocity_m_s;
    csv_->write(fmt::format("{},1,{:.10f},{:.10f},{:.4f},{:.4f},{:.4f},{:.4f}\n", a.t_ns,
                            g.latitude_deg, g.longitude_deg, g.height_m, v.x(), v.y(), v.z()));
  }

  const Trajectory& trajectory_;
  const GeodeticAnchor& anchor_;
  const track::Route& route_;
  std::string name_;
  TimeNs period_;
  Mount mount_;
  double ahead_of_front_;
  positioning::GnssErrorModel errors_;
  positioning::GnssVisibility visibility_;
  io::AppendFile* csv_ = nullptr;
};

// ---------------------------------------------------------------------------------------
// Odometer: the front pivot's distance along the track and the acceleration (render); the
// encoder and its slip episodes (commit). Every axle of the rigid train runs the same
// distance, so the odometer has no mount.

struct WheelTruth {
  TimeNs t_ns = 0;
  double distance_m = 0.0;
  double accel_m_s2 = 0.0;
};

class OdometerSensor final : public SensorOf<WheelTruth> {
 public:
  explicit OdometerSensor(const SensorSetup& setup)
      : OdometerSensor(setup, odometerBinding().read(setup.config)) {}
  OdometerSensor(const SensorSetup& setup, const OdometerConfig& c)
      : trajectory_(setup.context.trajectory),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        model_(c.spec, period_, RandomStream(setup.context.scenario.seed(), name_ + ".odometer")) {}

  std::string name() const override { return name_; }
  std::string kind() const override { return kOdometerKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kReadingsCsv, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null())
      csv_->write("t_ns,pulses,distance_m,speed_m_s,slip\n");
    else
      model_.restore(state);
  }
  nlohmann::json state() const override { return model_.state(); }

 private:
  WheelTruth read(std::int64_t k) const override {
    const TrajectorySample s = trajectory_.sample(k);
    return {s.t_ns, s.distance_m, s.accel_m_s2};
  }

  void write(std::int64_t k, WheelTruth& w) override {
    const positioning::OdometerReading r =
        model_.step(static_cast<std::uint64_t>(k), w.t_ns, w.distance_m, w.accel_m_s2);
    csv_->write(fmt::format("{},{},{:.6f},{:.6f},{}\n", w.t_ns, r.pulses, r.distance_m, r.speed_m_s,
                            r.slip));
  }

  const Trajectory& trajectory_;
  std::string name_;
  TimeNs period_;
  positioning::OdometerModel model_;
  io::AppendFile* csv_ = nullptr;
};

// ---------------------------------------------------------------------------------------
// Balise reader: the antenna's distance along the track and speed (render); the detector
// with its passage-time roots (commit). Balises lie along the main track.

positioning::BaliseDetector makeDetector(const SensorSetup& setup, const BaliseReaderConfig& c) {
  const track::Route& route = requireRoute(setup);
  std::vector<double> stations;
  for (const track::Block& b : route.blocks)
    if (b.type == track::BlockType::kStation)
      stations.push_back(route.track.vertical().at(b.chainage_begin_m).distance_m);
  return positioning::BaliseDetector(
      positioning::placeBalises(c.placement, route.track.distanceLength(), stations),
      c.detection_sigma_m, RandomStream(setup.context.scenario.seed(), c.basics.name + ".balises"));
}

class BaliseReader final : public SensorOf<positioning::AntennaState> {
 public:
  explicit BaliseReader(const SensorSetup& setup)
      : BaliseReader(setup, baliseReaderBinding().read(setup.config)) {}
  BaliseReader(const SensorSetup& setup, const BaliseReaderConfig& c)
      : trajectory_(setup.context.trajectory),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        ahead_of_front_(aheadOfFrontPivot(setup.context.scenario.json(), c.basics.mount.mount())),
        confidence_m_(c.location_accuracy_m + 3.0 * c.detection_sigma_m),
        detector_(makeDetector(setup, c)) {}

  std::string name() const override { return name_; }
  std::string kind() const override { return kBaliseReaderKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kReadingsCsv, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null())
      csv_->write("t_ns,group_id,balise_index,position_m,confidence_m\n");
    else
      detector_.restore(state);
  }
  nlohmann::json state() const override { return detector_.state(); }

 private:
  positioning::AntennaState read(std::int64_t k) const override {
    const TrajectorySample s = trajectory_.sample(k);
    return {s.t_ns, s.distance_m + ahead_of_front_, s.speed_m_s};
  }

  void write(std::int64_t, positioning::AntennaState& now) override {
    for (const positioning::BaliseEvent& e : detector_.step(now))
      csv_->write(fmt::format("{},{},{},{:.3f},{:.3f}\n", e.t, e.balise->group, e.balise->index,
                              e.balise->u_m, confidence_m_));
  }

  const Trajectory& trajectory_;
  std::string name_;
  TimeNs period_;
  double ahead_of_front_;
  double confidence_m_;
  positioning::BaliseDetector detector_;
  io::AppendFile* csv_ = nullptr;
};

}  // namespace

scenario::Param declareGnss() {
  return gnssBinding().declare(
      "gnss", "A GNSS receiver: latitude/longitude/height and velocity with correlated errors.");
}

scenario::Param declareOdometer() {
  return odometerBinding().declare("odometer", "A wheel encoder: pulses, distance and speed.");
}

scenario::Param declareBaliseReader() {
  return baliseReaderBinding().declare(
      "balise_reader", "Balise groups along the main track and the train's reader.");
}

void checkGnss(const scenario::Json& item, const std::string& path,
               std::vector<scenario::Problem>& problems) {
  gnssBinding().problems(gnssBinding().read(item), path, problems);
}
void checkOdometer(const scenario::Json& item, const std::string& path,
                   std::vector<scenario::Problem>& problems) {
  odometerBinding().problems(odometerBinding().read(item), path, problems);
}
void checkBaliseReader(const scenario::Json& item, const std::string& path,
                       std::vector<scenario::Problem>& problems) {
  baliseReaderBinding().problems(baliseReaderBinding().read(item), path, problems);
}

std::unique_ptr<Sensor> createGnss(const SensorSetup& setup) {
  return std::make_unique<GnssSensor>(setup);
}
std::unique_ptr<Sensor> createOdometer(const SensorSetup& setup) {
  return std::make_unique<OdometerSensor>(setup);
}
std::unique_ptr<Sensor> createBaliseReader(const SensorSetup& setup) {
  return std::make_unique<BaliseReader>(setup);
}

}  // namespace trainsim::sim
