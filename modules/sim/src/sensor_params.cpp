#include "trainsim/sim/sensor_params.hpp"

#include <fmt/format.h>

#include "trainsim/sim/config.hpp"

namespace trainsim::sim {
namespace {

constexpr const char* kName = "name";
constexpr const char* kMount = "mount";
constexpr const char* kPeriod = "period_ns";

const scenario::Binding<MountParams>& mountBinding() {
  static const scenario::Binding<MountParams> binding = [] {
    scenario::Binding<MountParams> b;
    bindBodyPosition(b, &MountParams::position_m);
    const scenario::Unit deg = scenario::units::kDegree;
    b.number("roll_deg", &MountParams::roll_rad, deg,
             "Roll about body x (right side down positive)")
        .range(-180, 180);
    b.number("pitch_deg", &MountParams::pitch_rad, deg,
             "Pitch about body y (nose up positive, as the body's pitch)")
        .range(-90, 90);
    b.number("yaw_deg", &MountParams::yaw_rad, deg, "Yaw about body z (to the left positive)")
        .range(-180, 180);
    return b;
  }();
  return binding;
}

}  // namespace

scenario::Binding<SensorBasics> sensorBasics(const BasicsSpec& spec) {
  scenario::Binding<SensorBasics> b;
  b.string(kName, &SensorBasics::name,
           fmt::format("Sensor name, unique across all sensors, not frames or instances "
                       "([a-z][a-z0-9_]{{0,63}}): "
                       "files {}. Unnamed items take the default name, numbered by position after "
                       "the first (_1, _2, …)",
                       spec.files))
      .numberedPerItem();
  b.integer(kPeriod, &SensorBasics::period_ns, "ns", spec.period_description)
      .range(static_cast<double>(spec.min_period_ns), static_cast<double>(spec.max_period_ns))
      .multipleOf(samplePeriodPath());
  if (spec.mount_description != nullptr)
    b.object(kMount, &SensorBasics::mount, mountBinding(),
             std::string(spec.mount_description) +
                 " (body axes: x forward, y left, z up; relative to the body reference point)");
  return b;
}

std::string readSensorName(const scenario::Json& item) {
  return item.at(kName).get<std::string>();
}

TimeNs readSensorPeriod(const scenario::Json& item) {
  return item.at(kPeriod).get<TimeNs>();
}

Mount readMount(const scenario::Json& item) {
  return mountBinding().read(item.at(kMount)).mount();
}

std::string mountPath(const std::string& item_path) {
  return fmt::format("{}.{}", item_path, kMount);
}

std::vector<std::string> sensorFiles(std::span<const char* const> patterns,
                                     const std::string& name) {
  std::vector<std::string> out;
  for (const char* pattern : patterns)
    out.push_back(fmt::format(fmt::runtime(pattern), name));
  return out;
}

double aheadOfFrontPivot(const scenario::Json& scenario, const Mount& mount) {
  const TrainConfig train = trainSection().read(scenario);
  return train.reference_point.x() + mount.position_m.x() - 0.5 * train.vehicle.bogie_spacing_m;
}

}  // namespace trainsim::sim
