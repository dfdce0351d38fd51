#include "positioning_sensors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/core/error.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/random.hpp"

namespace trainsim::sim {
namespace {

using scenario::Json;
using scenario::number;
using scenario::object;

std::filesystem::path sequenceFile(io::DatasetWriter& writer, const std::string& name) {
  return writer.sequenceDir().lexically_relative(writer.root()) / (name + ".csv");
}

const track::Route& requireRoute(const SensorSetup& setup, const char* kind) {
  if (setup.route == nullptr)
    throw RuntimeError(fmt::format("{} sensor needs the planned route", kind));
  return *setup.route;
}

// ---------------------------------------------------------------------------------------
// GNSS: fix = truth + Gauss–Markov (exactly discretised) + white error, in local east/north/up
// metres at the antenna; no fix while the antenna is in a tunnel, and none for
// `reacquisition_s` after it leaves one.

class GnssSensor final : public Sensor {
 public:
  explicit GnssSensor(const SensorSetup& setup)
      : name_(setup.config.at("name").get<std::string>()),
        period_(setup.config.at("period_ns").get<TimeNs>()),
        anchor_({setup.scenario.get<double>("geodetic_origin.latitude_deg"),
                 setup.scenario.get<double>("geodetic_origin.longitude_deg"),
                 setup.scenario.get<double>("geodetic_origin.height_m")}),
        route_(requireRoute(setup, "gnss")),
        rnd_(setup.scenario.seed(), name_ + ".gnss") {
    const Json& c = setup.config;
    antenna_ = {c.at("antenna").at("x_m").get<double>(), c.at("antenna").at("y_m").get<double>(),
                c.at("antenna").at("z_m").get<double>()};
    sigma_ = {c.at("horizontal_sigma_m").get<double>(), c.at("horizontal_sigma_m").get<double>(),
              c.at("vertical_sigma_m").get<double>()};
    white_ = c.at("white_sigma_m").get<double>();
    vel_sigma_ = c.at("velocity_sigma_m_s").get<double>();
    vel_gm_sigma_ = c.at("velocity_gm_sigma_m_s").get<double>();
    phi_ = std::exp(-toSeconds(period_) / c.at("correlation_time_s").get<double>());
    reacquire_ns_ = fromSeconds(c.at("reacquisition_s").get<double>());
    // Along the track, the antenna sits this far ahead of the front pivot (negative: behind).
    ahead_of_front_ = setup.scenario.get<double>("train.reference_point.x_m") + antenna_.x() -
                      0.5 * setup.scenario.get<double>("train.bogie_spacing_m");
  }
  std::string name() const override { return name_; }
  std::string kind() const override { return "gnss"; }
  TimeNs period() const override { return period_; }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null()) {
      csv_->write("t_ns,fix,latitude_deg,longitude_deg,height_m,ve_m_s,vn_m_s,vu_m_s\n");
    } else {
      for (std::size_t a = 0; a < 3; ++a) {
        gm_[a] = state.at("gm").at(a).get<double>();
        vel_gm_[a] = state.at("vel_gm").at(a).get<double>();
      }
      started_ = state.at("started").get<bool>();
      last_tunnel_ns_ = state.at("last_tunnel_ns").get<TimeNs>();
    }
  }

  bool inTunnel(double chainage) const {
    const track::Block& b = route_.blockAt(chainage);
    return b.type == track::BlockType::kTunnel && chainage >= b.chainage_begin_m &&
           chainage <= b.chainage_end_m;
  }

  void capture(std::int64_t k, const TrajectorySample& s) override {
    const Eigen::Matrix3d r = s.q_world_body.toRotationMatrix();
    const Eigen::Vector3d p = s.p_world + r * antenna_;
    const Eigen::Vector3d v = s.v_world + r * s.w_body.cross(antenna_);
    const double chainage = s.chainage_m + ahead_of_front_;
    const auto n = rnd_.normal4(static_cast<std::uint64_t>(k), 0);
    const auto m = rnd_.normal4(static_cast<std::uint64_t>(k), 1);
    const auto vn = rnd_.normal4(static_cast<std::uint64_t>(k), 3);
    // The error processes run through outages too (the satellites' geometry does not stop).
    // Exact Gauss–Markov steps; the first reading starts from the stationary distribution.
    const double q = started_ ? std::sqrt(1 - phi_ * phi_) : 1.0;
    const double f = started_ ? phi_ : 0.0;
    for (std::size_t a = 0; a < 3; ++a) {
      gm_[a] = f * gm_[a] + sigma_[static_cast<int>(a)] * q * n[a];
      vel_gm_[a] = f * vel_gm_[a] + vel_gm_sigma_ * q * vn[a];
    }
    started_ = true;
    if (inTunnel(chainage))
      last_tunnel_ns_ = s.t_ns;
    const bool fix = last_tunnel_ns_ < 0 || s.t_ns - last_tunnel_ns_ >= reacquire_ns_;
    if (!fix) {
      csv_->write(fmt::format("{},0,,,,,,\n", s.t_ns));
      return;
    }
    const Eigen::Vector3d err(gm_[0] + white_ * n[3], gm_[1] + white_ * m[0],
                              gm_[2] + white_ * m[1]);
    // Errors are east/north/up at the antenna; the anchor frame's axes differ from the local
    // ones by the angle subtended at the Earth's centre, which rotateAnchorFromLocalEnu gives.
    const Eigen::Matrix3d r_anchor_local = anchor_.rotationAnchorFromLocalEnu(p);
    const Eigen::Vector3d p_meas = p + r_anchor_local * err;
    const GeodeticPoint g = anchor_.fromEnu(p_meas);
    const Eigen::Vector3d v_local = r_anchor_local.transpose() * v;
    const auto w = rnd_.normal4(static_cast<std::uint64_t>(k), 2);
    csv_->write(fmt::format("{},1,{:.10f},{:.10f},{:.4f},{:.4f},{:.4f},{:.4f}\n", s.t_ns,
                            g.latitude_deg, g.longitude_deg, g.height_m,
                            v_local.x() + vel_gm_[0] + vel_sigma_ * w[0],
                            v_local.y() + vel_gm_[1] + vel_sigma_ * w[1],
                            v_local.z() + vel_gm_[2] + vel_sigma_ * w[2]));
  }

  nlohmann::json state() const override {
    return {{"gm", {gm_[0], gm_[1], gm_[2]}},
            {"vel_gm", {vel_gm_[0], vel_gm_[1], vel_gm_[2]}},
            {"started", started_},
            {"last_tunnel_ns", last_tunnel_ns_}};
  }

 private:
  std::string name_;
  TimeNs period_;
  GeodeticAnchor anchor_;
  const track::Route& route_;
  RandomStream rnd_;
  Eigen::Vector3d antenna_, sigma_;
  double white_ = 0, vel_sigma_ = 0, vel_gm_sigma_ = 0, phi_ = 0, ahead_of_front_ = 0;
  TimeNs reacquire_ns_ = 0;
  std::array<double, 3> gm_{};
  std::array<double, 3> vel_gm_{};
  bool started_ = false;
  TimeNs last_tunnel_ns_ = -1;
  io::AppendFile* csv_ = nullptr;
};

// ---------------------------------------------------------------------------------------
// Odometer: the encoder sees the wheel turn (1 + ε)·ds (+ slip or slide during an episode);
// pulses are counted on whole pulses of π D / N; distance = pulses · π D / N and speed is the
// pulse difference over the period.

class OdometerSensor final : public Sensor {
 public:
  explicit OdometerSensor(const SensorSetup& setup)
      : name_(setup.config.at("name").get<std::string>()),
        period_(setup.config.at("period_ns").get<TimeNs>()),
        rnd_(setup.scenario.seed(), name_ + ".odometer") {
    const Json& c = setup.config;
    pulse_m_ = std::numbers::pi * c.at("wheel_diameter_m").get<double>() /
               c.at("pulses_per_revolution").get<double>();
    scale_error_ = c.at("scale_error").get<double>();
    const Json& slip = c.at("slip");
    slip_on_ = slip.at("enabled").get<bool>();
    accel_threshold_ = slip.at("accel_threshold_m_s2").get<double>();
    brake_threshold_ = slip.at("brake_threshold_m_s2").get<double>();
    rate_ = slip.at("rate_per_s").get<double>();
    dur_min_ = slip.at("duration_min_s").get<double>();
    dur_max_ = slip.at("duration_max_s").get<double>();
    mag_max_ = slip.at("magnitude_max").get<double>();
  }
  std::string name() const override { return name_; }
  std::string kind() const override { return "odometer"; }
  TimeNs period() const override { return period_; }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null()) {
      csv_->write("t_ns,pulses,distance_m,speed_m_s,slip\n");
    } else {
      encoder_m_ = state.at("encoder_m").get<double>();
      last_u_ = state.at("last_u").get<double>();
      last_pulses_ = state.at("last_pulses").get<std::int64_t>();
      episode_end_ns_ = state.at("episode_end_ns").get<TimeNs>();
      episode_factor_ = state.at("episode_factor").get<double>();
      started_ = true;
    }
  }

  void capture(std::int64_t k, const TrajectorySample& s) override {
    if (!started_) {
      last_u_ = s.distance_m;
      started_ = true;
    }
    // Slip (traction) and slide (braking) episodes start only under high acceleration.
    if (slip_on_ && s.t_ns >= episode_end_ns_) {
      episode_factor_ = 0.0;
      const auto u = rnd_.uniform4(static_cast<std::uint64_t>(k));
      const bool traction = s.accel_m_s2 > accel_threshold_;
      const bool braking = s.accel_m_s2 < -brake_threshold_;
      if ((traction || braking) && u[0] < rate_ * toSeconds(period_)) {
        const double magnitude = 0.02 + (mag_max_ - 0.02) * u[1];
        episode_factor_ = traction ? magnitude : -std::min(magnitude, 0.9);
        episode_end_ns_ = s.t_ns + fromSeconds(dur_min_ + (dur_max_ - dur_min_) * u[2]);
      }
    }
    const double ds = s.distance_m - last_u_;
    last_u_ = s.distance_m;
    encoder_m_ += (1.0 + scale_error_) * (1.0 + episode_factor_) * ds;
    const auto pulses = static_cast<std::int64_t>(std::floor(encoder_m_ / pulse_m_));
    const double speed = static_cast<double>(pulses - last_pulses_) * pulse_m_ / toSeconds(period_);
    last_pulses_ = pulses;
    const int flag = episode_factor_ > 0 ? 1 : episode_factor_ < 0 ? -1 : 0;
    csv_->write(fmt::format("{},{},{:.6f},{:.6f},{}\n", s.t_ns, pulses,
                            static_cast<double>(pulses) * pulse_m_, k == 0 ? 0.0 : speed, flag));
  }

  nlohmann::json state() const override {
    return {{"encoder_m", encoder_m_},
            {"last_u", last_u_},
            {"last_pulses", last_pulses_},
            {"episode_end_ns", episode_end_ns_},
            {"episode_factor", episode_factor_}};
  }

 private:
  std::string name_;
  TimeNs period_;
  RandomStream rnd_;
  double pulse_m_ = 0, scale_error_ = 0;
  bool slip_on_ = false;
  double accel_threshold_ = 0, brake_threshold_ = 0, rate_ = 0, dur_min_ = 0, dur_max_ = 0,
         mag_max_ = 0;
  double encoder_m_ = 0, last_u_ = 0;
  std::int64_t last_pulses_ = 0;
  TimeNs episode_end_ns_ = 0;
  double episode_factor_ = 0;
  bool started_ = false;
  io::AppendFile* csv_ = nullptr;
};

// ---------------------------------------------------------------------------------------
// Balise reader: balise groups at fixed spacing along the track (plus one before every
// station), read by an antenna `antenna_offset_m` ahead of the front pivot. The passage time
// is found inside the sample interval on the cubic Hermite interpolant of the antenna's
// distance (exact speeds at both ends), so events carry their own time, not the sample's.

struct Balise {
  int group;
  int index;
  double u_m;  // distance along the track (3D), where the antenna reads it
};

class BaliseReader final : public Sensor {
 public:
  explicit BaliseReader(const SensorSetup& setup)
      : name_(setup.config.at("name").get<std::string>()),
        period_(setup.config.at("period_ns").get<TimeNs>()),
        rnd_(setup.scenario.seed(), name_ + ".balises") {
    const Json& c = setup.config;
    offset_ = c.at("antenna_offset_m").get<double>();
    accuracy_ = c.at("location_accuracy_m").get<double>();
    detection_sigma_ = c.at("detection_sigma_m").get<double>();
    const track::Route& route = requireRoute(setup, "balise");
    const double end = route.track.distanceLength();
    const double spacing = c.at("group_spacing_m").get<double>();
    const int per_group = c.at("balises_per_group").get<int>();
    const double within = c.at("balise_spacing_m").get<double>();
    std::vector<double> groups;
    for (double u = c.at("first_group_m").get<double>(); u + within * per_group < end; u += spacing)
      groups.push_back(u);
    const double approach = c.at("station_approach_m").get<double>();
    if (approach > 0.0)
      for (const track::Block& b : route.blocks)
        if (b.type == track::BlockType::kStation) {
          const double u = route.track.vertical().at(b.chainage_begin_m).distance_m - approach;
          if (u > 0.0)
            groups.push_back(u);
        }
    std::sort(groups.begin(), groups.end());
    for (std::size_t g = 0; g < groups.size(); ++g)
      for (int i = 0; i < per_group; ++i)
        balises_.push_back({static_cast<int>(g), i, groups[g] + within * i});
  }
  std::string name() const override { return name_; }
  std::string kind() const override { return "balise_reader"; }
  TimeNs period() const override { return period_; }
  const std::vector<Balise>& balises() const { return balises_; }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    csv_ = &writer.appendFile(sequenceFile(writer, name_));
    if (state.is_null()) {
      csv_->write("t_ns,group_id,balise_index,position_m,confidence_m\n");
    } else {
      prev_ = {state.at("t_ns").get<TimeNs>(), state.at("u").get<double>(),
               state.at("v").get<double>()};
      next_ = state.at("next").get<std::size_t>();
      started_ = true;
    }
  }

  void capture(std::int64_t, const TrajectorySample& s) override {
    const Point cur{s.t_ns, s.distance_m + offset_, s.speed_m_s};
    if (!started_) {
      // Balises behind the antenna at the start are never passed.
      while (next_ < balises_.size() && balises_[next_].u_m <= cur.u)
        ++next_;
      started_ = true;
      prev_ = cur;
      return;
    }
    while (next_ < balises_.size()) {
      const Balise& b = balises_[next_];
      // Detected where the antenna is at the balise plus the detection error.
      const double err = detection_sigma_ * rnd_.normal4(static_cast<std::uint64_t>(next_))[0];
      const double at = b.u_m + err;
      if (at > cur.u)
        break;
      const TimeNs t = passage(prev_, cur, std::max(at, prev_.u));
      csv_->write(fmt::format("{},{},{},{:.3f},{:.3f}\n", t, b.group, b.index, b.u_m,
                              accuracy_ + 3.0 * detection_sigma_));
      ++next_;
    }
    prev_ = cur;
  }

  nlohmann::json state() const override {
    return {{"t_ns", prev_.t_ns}, {"u", prev_.u}, {"v", prev_.v}, {"next", next_}};
  }

 private:
  struct Point {
    TimeNs t_ns = 0;
    double u = 0.0, v = 0.0;
  };

  // Time at which the Hermite cubic through (t0, u0, v0) and (t1, u1, v1) reaches `target`.
  static TimeNs passage(const Point& a, const Point& b, double target) {
    const double h = toSeconds(b.t_ns - a.t_ns);
    auto u = [&](double x) {
      const double x2 = x * x, x3 = x2 * x;
      return (2 * x3 - 3 * x2 + 1) * a.u + (x3 - 2 * x2 + x) * h * a.v + (-2 * x3 + 3 * x2) * b.u +
             (x3 - x2) * h * b.v;
    };
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (u(mid) < target ? lo : hi) = mid;
    }
    return a.t_ns + static_cast<TimeNs>(std::llround(hi * static_cast<double>(b.t_ns - a.t_ns)));
  }

  std::string name_;
  TimeNs period_;
  RandomStream rnd_;
  double offset_ = 0, accuracy_ = 0, detection_sigma_ = 0;
  std::vector<Balise> balises_;
  std::size_t next_ = 0;
  Point prev_;
  bool started_ = false;
  io::AppendFile* csv_ = nullptr;
};

scenario::Param period(TimeNs default_ns, const std::string& what) {
  return scenario::integer("period_ns", default_ns, "ns", what)
      .range(100'000, 60'000'000'000)
      .multipleOf("trajectory.sample_period_ns");
}

}  // namespace

scenario::Param declareGnss() {
  return object(
      "gnss", "A GNSS receiver: latitude/longitude/height and velocity with correlated errors.",
      {scenario::string("name", "gnss", "Sensor name: file <name>.csv"),
       period(1'000'000'000, "Fix period (1 Hz by default)"),
       object("antenna", "Antenna position relative to the body reference point (body axes)",
              {number("x_m", 0, "m", "Forward").range(-100, 100),
               number("y_m", 0, "m", "Left").range(-10, 10),
               number("z_m", 4.0, "m", "Up").range(-10, 10)}),
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
      {scenario::string("name", "odometer", "Sensor name: file <name>.csv"),
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
      {scenario::string("name", "balises", "Sensor name: file <name>.csv"),
       period(10'000'000, "Reader polling period (events carry their own time)"),
       number("antenna_offset_m", 2.0, "m", "Reader antenna ahead of the front bogie pivot")
           .range(-50, 50),
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
