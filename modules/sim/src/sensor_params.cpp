#include "trainsim/sim/sensor_params.hpp"

#include <fmt/format.h>

namespace trainsim::sim {
namespace {
constexpr const char* kName = "name";
constexpr const char* kPeriod = "period_ns";
constexpr const char* kMount = "mount";
}  // namespace

scenario::Param declareSensorName(const std::string& base, const std::string& files) {
  return scenario::string(kName, base,
                          "Sensor name, unique across all sensors (letters, digits, '_', '-', "
                          "'.'): files " +
                              files + ". Unnamed items are " + base + ", " + base + "_1, …")
      .numberedPerItem();
}

std::string readSensorName(const scenario::Json& config) {
  return config.at(kName).get<std::string>();
}

scenario::Param declarePeriod(TimeNs default_ns, TimeNs minimum_ns, TimeNs maximum_ns,
                              const std::string& description) {
  return scenario::integer(kPeriod, default_ns, "ns", description)
      .range(static_cast<double>(minimum_ns), static_cast<double>(maximum_ns))
      .multipleOf("trajectory.sample_period_ns");
}

std::vector<std::string> sensorFiles(std::span<const char* const> patterns,
                                     const std::string& name) {
  std::vector<std::string> out;
  for (const char* pattern : patterns)
    out.push_back(fmt::format(fmt::runtime(pattern), name));
  return out;
}

TimeNs readPeriod(const scenario::Json& config) {
  return config.at(kPeriod).get<TimeNs>();
}

scenario::Param declareMount(const std::string& description, MountDefaults d) {
  using scenario::number;
  return scenario::object(
      kMount,
      description + " (body axes: x forward, y left, z up; relative to the body reference point)",
      {number("x_m", d.x_m, "m", "Forward").range(-100, 100),
       number("y_m", d.y_m, "m", "Left").range(-10, 10),
       number("z_m", d.z_m, "m", "Up").range(-10, 10),
       number("roll_deg", 0, "deg", "Roll about body x (right side down positive)")
           .range(-180, 180),
       number("pitch_deg", 0, "deg", "Pitch about body y (nose up positive, as the body's pitch)")
           .range(-90, 90),
       number("yaw_deg", 0, "deg", "Yaw about body z (to the left positive)").range(-180, 180)});
}

Mount readMount(const scenario::Json& config) {
  const scenario::Json& m = config.at(kMount);
  Mount mount;
  mount.position_m = {m.at("x_m").get<double>(), m.at("y_m").get<double>(),
                      m.at("z_m").get<double>()};
  mount.r_body_sensor = attitude(m.at("yaw_deg").get<double>() * kRadPerDeg,
                                 m.at("pitch_deg").get<double>() * kRadPerDeg,
                                 m.at("roll_deg").get<double>() * kRadPerDeg);
  return mount;
}

double aheadOfFrontPivot(const scenario::Json& scenario, const Mount& mount) {
  const scenario::Json& train = scenario.at("train");
  return train.at("reference_point").at("x_m").get<double>() + mount.position_m.x() -
         0.5 * train.at("bogie_spacing_m").get<double>();
}

}  // namespace trainsim::sim
