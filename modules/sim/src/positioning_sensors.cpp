#include "positioning_sensors.hpp"

#include <fmt/format.h>

#include "trainsim/core/error.hpp"
#include "trainsim/positioning/balise.hpp"
#include "trainsim/positioning/gnss.hpp"
#include "trainsim/positioning/odometer.hpp"
#include "trainsim/sim/sensor_params.hpp"

namespace trainsim::sim {
namespace {

using scenario::Json;
using scenario::number;
using scenario::object;

// Thin adapters: the physics is in modules/positioning; these read the scenario, take the
// truth from the trajectory in render() and run the models and write CSV rows in commit().

// A sensor's readings file: <name>.csv in the sequence folder.
std::filesystem::path sequenceFile(io::DatasetWriter& writer, const std::string& name) {
  return writer.sequenceDir().lexically_relative(writer.root()) /
         sensorFiles(kReadingsCsv, name).front();
}

const track::Route& requireRoute(const SensorSetup& setup) {
  if (setup.context.route == nullptr)
    throw RuntimeError(fmt::format("{}: this sensor needs the planned route", setup.path));
  return *setup.context.route;
}

// ---------------------------------------------------------------------------------------
// GNSS receiver: the antenna's true position and velocity (render), the error model and the
// tunnel outage (commit).

struct AntennaTruth {
  TimeNs t_ns = 0;
  Eigen::Vector3d p_world, v_world;
  bool in_tunnel = false;
};

class GnssSensor final : public SensorOf<AntennaTruth> {
 public:
  explicit GnssSensor(const SensorSetup& setup)
      : trajectory_(setup.context.trajectory),
        anchor_(setup.context.anchor),
        route_(requireRoute(setup)),
        name_(readSensorName(setup.config)),
        period_(readPeriod(setup.config)),
        mount_(readMount(setup.config)),
        ahead_of_front_(aheadOfFrontPivot(setup.context.scenario.json(), mount_)),
        errors_(spec(setup.config), period_,
                RandomStream(setup.context.scenario.seed(), name_ + ".gnss")),
        outage_(fromSeconds(setup.config.at("reacquisition_s").get<double>())) {}

  static positioning::GnssErrorSpec spec(const Json& c) {
    positioning::GnssErrorSpec e;
    e.horizontal_sigma_m = c.at("horizontal_sigma_m").get<double>();
    e.vertical_sigma_m = c.at("vertical_sigma_m").get<double>();
    e.correlation_time_s = c.at("correlation_time_s").get<double>();
    e.white_sigma_m = c.at("white_sigma_m").get<double>();
    e.velocity_sigma_m_s = c.at("velocity_sigma_m_s").get<double>();
    e.velocity_gm_sigma_m_s = c.at("velocity_gm_sigma_m_s").get<double>();
    return e;
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return "gnss"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return sensorFiles(kReadingsCsv, name_); }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null()) {
      csv_->write("t_ns,fix,latitude_deg,longitude_deg,height_m,ve_m_s,vn_m_s,vu_m_s\n");
    } else {
      errors_.restore(state.at("errors"));
      outage_.restore(state.at("last_tunnel_ns").get<TimeNs>());
    }
  }

  nlohmann::json state() const override {
    return {{"errors", errors_.state()}, {"last_tunnel_ns", outage_.lastTunnel()}};
  }

 private:
  AntennaTruth read(std::int64_t k) const override {
    const TrajectorySample s = trajectory_.sample(k);
    const Eigen::Matrix3d r = s.q_world_body.toRotationMatrix();
    const Eigen::Vector3d& arm = mount_.position_m;
    const double chainage = s.chainage_m + ahead_of_front_;
    const track::Block& b = route_.blockAt(chainage);
    return {s.t_ns, s.p_world + r * arm, s.v_world + r * s.w_body.cross(arm),
            b.type == track::BlockType::kTunnel && chainage >= b.chainage_begin_m &&
                chainage <= b.chainage_end_m};
  }

  void write(std::int64_t k, AntennaTruth& a) override {
    const positioning::GnssErrors e = errors_.step(static_cast<std::uint64_t>(k));
    if (!outage_.fix(a.t_ns, a.in_tunnel)) {
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
  positioning::GnssOutage outage_;
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
      : trajectory_(setup.context.trajectory),
        name_(readSensorName(setup.config)),
        period_(readPeriod(setup.config)),
        model_(spec(setup.config), period_,
               RandomStream(setup.context.scenario.seed(), name_ + ".odometer")) {}

  static positioning::OdometerSpec spec(const Json& c) {
    positioning::OdometerSpec o;
    o.wheel_diameter_m = c.at("wheel_diameter_m").get<double>();
    o.pulses_per_revolution = c.at("pulses_per_revolution").get<int>();
    o.scale_error = c.at("scale_error").get<double>();
    const Json& slip = c.at("slip");
    o.slip.enabled = slip.at("enabled").get<bool>();
    o.slip.accel_threshold_m_s2 = slip.at("accel_threshold_m_s2").get<double>();
    o.slip.brake_threshold_m_s2 = slip.at("brake_threshold_m_s2").get<double>();
    o.slip.rate_per_s = slip.at("rate_per_s").get<double>();
    o.slip.duration_min_s = slip.at("duration_min_s").get<double>();
    o.slip.duration_max_s = slip.at("duration_max_s").get<double>();
    o.slip.magnitude_max = slip.at("magnitude_max").get<double>();
    return o;
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return "odometer"; }
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

positioning::BaliseDetector makeDetector(const SensorSetup& setup, const std::string& name) {
  const Json& c = setup.config;
  const track::Route& route = requireRoute(setup);
  positioning::BalisePlacement p;
  p.first_group_m = c.at("first_group_m").get<double>();
  p.group_spacing_m = c.at("group_spacing_m").get<double>();
  p.balises_per_group = c.at("balises_per_group").get<int>();
  p.balise_spacing_m = c.at("balise_spacing_m").get<double>();
  p.station_approach_m = c.at("station_approach_m").get<double>();
  std::vector<double> stations;
  for (const track::Block& b : route.blocks)
    if (b.type == track::BlockType::kStation)
      stations.push_back(route.track.vertical().at(b.chainage_begin_m).distance_m);
  return positioning::BaliseDetector(
      positioning::placeBalises(p, route.track.distanceLength(), stations),
      c.at("detection_sigma_m").get<double>(),
      RandomStream(setup.context.scenario.seed(), name + ".balises"));
}

class BaliseReader final : public SensorOf<positioning::AntennaState> {
 public:
  explicit BaliseReader(const SensorSetup& setup)
      : trajectory_(setup.context.trajectory),
        name_(readSensorName(setup.config)),
        period_(readPeriod(setup.config)),
        ahead_of_front_(aheadOfFrontPivot(setup.context.scenario.json(), readMount(setup.config))),
        confidence_m_(setup.config.at("location_accuracy_m").get<double>() +
                      3.0 * setup.config.at("detection_sigma_m").get<double>()),
        detector_(makeDetector(setup, name_)) {}

  std::string name() const override { return name_; }
  std::string kind() const override { return "balise_reader"; }
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

scenario::Param period(TimeNs default_ns, const std::string& what) {
  return declarePeriod(default_ns, 100'000, 60'000'000'000, what);
}

}  // namespace

scenario::Param declareGnss() {
  return object(
      "gnss", "A GNSS receiver: latitude/longitude/height and velocity with correlated errors.",
      {declareSensorName("gnss", "<name>.csv"),
       period(1'000'000'000, "Fix period (1 Hz by default)"),
       declareMount("Antenna phase centre (its attitude does not matter)", {0.0, 0.0, 4.0}),
       number("horizontal_sigma_m", 1.5, "m", "Gauss-Markov horizontal error, 1 sigma per axis")
           .range(0, 1000),
       number("vertical_sigma_m", 3.0, "m", "Gauss-Markov vertical error, 1 sigma").range(0, 1000),
       number("correlation_time_s", 120, "s", "Correlation time of the Gauss-Markov error")
           .range(0.1, 1e5),
       number("white_sigma_m", 0.3, "m", "White position noise, 1 sigma per axis").range(0, 100),
       number("velocity_sigma_m_s", 0.05, "m/s", "White velocity noise, 1 sigma per axis")
           .range(0, 10),
       number("velocity_gm_sigma_m_s", 0.02, "m/s",
              "Gauss-Markov velocity error (same correlation time), 1 sigma per axis")
           .range(0, 10),
       number("reacquisition_s", 5.0, "s", "No fix for this long after leaving a tunnel")
           .range(0, 600)});
}

scenario::Param declareOdometer() {
  return object(
      "odometer", "A wheel encoder: pulses, distance and speed.",
      {declareSensorName("odometer", "<name>.csv"),
       period(10'000'000, "Output period (100 Hz by default)"),
       number("wheel_diameter_m", 0.92, "m", "Nominal wheel diameter").range(0.3, 2.0),
       scenario::integer("pulses_per_revolution", 200, "", "Encoder pulses per wheel turn")
           .range(1, 100000),
       number("scale_error", 0.005, "",
              "Distance scale error: the encoder reads (1 + e) times the distance travelled "
              "(worn or mis-calibrated wheel)")
           .range(-0.2, 0.2),
       object("slip", "Wheel slip (traction) and slide (braking) episodes",
              {scenario::boolean("enabled", true, "Simulate slip and slide"),
               number("accel_threshold_m_s2", 0.5, "m/s^2", "Slip only above this acceleration")
                   .range(0, 10),
               number("brake_threshold_m_s2", 0.4, "m/s^2", "Slide only above this braking")
                   .range(0, 10),
               number("rate_per_s", 0.02, "1/s", "Episode start rate while above threshold")
                   .range(0, 100),
               number("duration_min_s", 1.0, "s", "Shortest episode").range(0.01, 600),
               number("duration_max_s", 4.0, "s", "Longest episode").range(0.01, 600),
               number("magnitude_max", 0.15, "", "Largest relative speed error of an episode")
                   .range(0.02, 0.9)})});
}

scenario::Param declareBaliseReader() {
  return object(
      "balise_reader", "Balise groups along the main track and the train's reader.",
      {declareSensorName("balises", "<name>.csv"),
       period(10'000'000, "Reader polling period (events carry their own time)"),
       declareMount("Reader antenna under the carbody; a balise is read when the antenna's "
                    "x passes it (2 m ahead of the front bogie pivot by default)",
                    {10.75, 0.0, -0.5}),
       number("first_group_m", 200, "m", "Distance of the first group from the route start")
           .range(0, 1e7),
       number("group_spacing_m", 1000, "m", "Distance between balise groups").range(10, 1e6),
       scenario::integer("balises_per_group", 2, "", "Balises in a group").range(1, 8),
       number("balise_spacing_m", 3.0, "m", "Distance between balises of a group").range(0.5, 20),
       number("station_approach_m", 50, "m", "Extra group this far before each station; 0: none")
           .range(0, 5000),
       number("location_accuracy_m", 1.0, "m", "Group location accuracy (ETCS Q_LOCACC)")
           .range(0, 63),
       number("detection_sigma_m", 0.3, "m", "Where the reader detects the balise, 1 sigma")
           .range(0, 5)});
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
