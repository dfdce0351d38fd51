#include "trainsim/sim/sensor_registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>

#include "camera_config.hpp"
#include "camera_sensor.hpp"
#include "imu_sensor.hpp"
#include "lidar_config.hpp"
#include "lidar_sensor.hpp"
#include "positioning_sensors.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/frame_clock.hpp"
#include "trainsim/sim/instance_table.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/sim/sensor_params.hpp"

namespace trainsim::sim {

// The sensor registration table: one line per sensor kind.
//
// How to add a sensor kind:
//   1. Put the physics in a module below sim (e.g. modules/inertial) and implement
//      trainsim::sim::Sensor (sensor.hpp) as a thin adapter in modules/sim/src (e.g.
//      imu_sensor.cpp), respecting the resume contract stated there.
//   2. Give it a config struct with `SensorBasics basics` and its parameters, and a
//      scenario::Binding of it that embeds sensorBasics(...) (sensor_params.hpp) and binds each
//      parameter once (units in the keys); `scenario::Param declareX()` returns its
//      declaration and `std::unique_ptr<Sensor> createX(const SensorSetup&)` reads it.
//   3. Add one line below: {"<plural key>", "<one-line description>", &declareX, &createX,
//      &checkX (the binding's checks: binding.problems(binding.read(item), path, out)), &warnX
//      (the settings it takes that may not be meant; nullptr if none), kXFiles},
//      where kXFiles lists the files the sensor writes ("{}.csv" for <name>.csv; sensor_params.hpp)
//      and its outputs() returns (sensorFiles).
// The schema (sensors.<key>[]), validation, `trainsim schema`, docs/SCENARIO.md, the studio's
// panels and the run loop pick the new kind up from this table; nothing else changes.
//
// The frame clock that writes times.txt and poses.txt is not a registered kind: every
// dataset has exactly one (frame_clock.hpp).
namespace {
constexpr std::array<SensorKind, 6> kSensorKinds = {
    SensorKind{"imus", "9-axis IMUs (accelerometer, gyroscope, magnetometer)", &declareImu,
               &createImu, &checkImu, nullptr, kImuCsvs},
    SensorKind{"gnss_receivers", "GNSS receivers", &declareGnss, &createGnss, &checkGnss, nullptr,
               kReadingsCsv},
    SensorKind{"odometers", "Wheel odometers", &declareOdometer, &createOdometer, &checkOdometer,
               nullptr, kReadingsCsv},
    SensorKind{"balise_readers", "Balise readers (and the balise groups they read)",
               &declareBaliseReader, &createBaliseReader, &checkBaliseReader, nullptr,
               kReadingsCsv},
    SensorKind{"lidars", "Rotating multi-beam LiDARs (Embree)", &declareLidar, &createLidar,
               &checkLidar, &warnLidar, kReadingsCsv, /*frame_synchronous=*/true},
    SensorKind{"cameras", "Cameras (VTK offscreen rendering)", &declareCamera, &createCamera,
               &checkCamera, &warnCamera, kReadingsCsv, /*frame_synchronous=*/true},
};

constexpr const char* kSensors = "sensors";

// A sensor name becomes file names (and folder names, topics, column prefixes): an identifier
// [a-z][a-z0-9_]{0,63}, which no file system, shell or dataset reader misreads.
bool isIdentifier(const std::string& name) {
  if (name.empty() || name.size() > 64 || !(name.front() >= 'a' && name.front() <= 'z'))
    return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// The kind a sensor's create function belongs to.
const SensorKind& kindOf(std::unique_ptr<Sensor> (*create)(const SensorSetup&)) {
  return *std::find_if(kSensorKinds.begin(), kSensorKinds.end(),
                       [&](const SensorKind& k) { return k.create == create; });
}

// No LiDAR beam leaving its head inside the train's body: its rays would end on the body.
void checkLidarsClearOfTheBody(const scenario::Json& resolved,
                               std::vector<scenario::Problem>& problems) {
  const SensorKind& lidars = kindOf(&createLidar);
  const TrainConfig train = trainSection().read(resolved);
  const scenario::Json& list = resolved.at(kSensors).at(lidars.key);
  for (std::size_t i = 0; i < list.size(); ++i)
    checkLidarClearOfTheBody(list[i], train, fmt::format("{}.{}[{}]", kSensors, lidars.key, i),
                             problems);
}

// No LiDAR or camera at or below the top of rail: it would be in the track bed, and see the
// world from under the ground.
void checkPerceptionSensorsAboveTheRails(const scenario::Json& resolved,
                                         std::vector<scenario::Problem>& problems) {
  const TrainConfig train = trainSection().read(resolved);
  for (const SensorKind& kind : sensorKinds()) {
    if (!kind.frame_synchronous)
      continue;
    const scenario::Json& list = resolved.at(kSensors).at(kind.key);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const double height = readMount(list[i]).position_m.z() + train.reference_point.z();
      if (height <= 0.0)
        problems.push_back(
            {mountPath(fmt::format("{}.{}[{}]", kSensors, kind.key, i)),
             fmt::format("the sensor would be {:.2f} m above the top of rail (z_m plus "
                         "train.reference_point.z_m): in the track bed or under it; mount it above "
                         "the rails",
                         height)});
    }
  }
}
// One weather for every perception sensor: a LiDAR and a camera given different fog record two
// different days, one showing fog the other does not. Said of each that differs from the first.
void warnAboutDifferentFog(const scenario::Json& resolved, std::vector<std::string>& out) {
  struct Fog {
    std::string path;
    double visibility_m, height_m;
  };
  std::vector<Fog> fogs;
  const auto add = [&](const SensorKind& kind, auto read) {
    const scenario::Json& list = resolved.at(kSensors).at(kind.key);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto c = read(list[i]);
      fogs.push_back(
          {fmt::format("{}.{}[{}]", kSensors, kind.key, i), c.fog_visibility_m, c.fog_height_m});
    }
  };
  add(kindOf(&createLidar), [](const scenario::Json& item) { return lidarBinding().read(item); });
  add(kindOf(&createCamera), [](const scenario::Json& item) { return cameraBinding().read(item); });
  const auto text = [](const Fog& f) {
    return f.visibility_m > 0.0 ? fmt::format("fog_visibility_m {} m and fog_height_m {} m",
                                              f.visibility_m, f.height_m)
                                : std::string("no fog (fog_visibility_m 0)");
  };
  for (std::size_t i = 1; i < fogs.size(); ++i)
    if (fogs[i].visibility_m != fogs[0].visibility_m ||
        (fogs[i].visibility_m > 0.0 && fogs[i].height_m != fogs[0].height_m))
      out.push_back(fmt::format(
          "{}: {}, but {} has {}: the sensors record different weather; give every LiDAR and "
          "camera the same fog_visibility_m and fog_height_m",
          fogs[i].path, text(fogs[i]), fogs[0].path, text(fogs[0])));
}
}  // namespace

std::span<const SensorKind> sensorKinds() {
  return kSensorKinds;
}

Eigen::Isometry3d referenceCameraPose(const scenario::Json& resolved) {
  const scenario::Json& cameras = resolved.at(kSensors).at(kindOf(&createCamera).key);
  if (!cameras.empty())
    return cameraBodyPose(cameras[0]);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotationBodyFromKittiCamera();
  return T;
}

SensorContext makeSensorContext(const scenario::Scenario& scenario, const Trajectory& trajectory,
                                const track::Route* route, const track::Layout* layout) {
  return SensorContext{
      scenario, geodeticAnchor(scenario.json()),     trajectory, route, layout, nullptr, nullptr,
      nullptr,  referenceCameraPose(scenario.json())};
}

std::vector<std::string> sensorWarnings(const scenario::Json& resolved) {
  std::vector<std::string> out;
  for (const SensorKind& kind : sensorKinds()) {
    const scenario::Json& list = resolved.at(kSensors).at(kind.key);
    for (std::size_t i = 0; i < list.size() && kind.warn != nullptr; ++i) {
      std::vector<std::string> lines = kind.warn(
          resolved, list[i], fmt::format("{}.{}[{}]", kSensors, kind.key, i), static_cast<int>(i));
      out.insert(out.end(), std::make_move_iterator(lines.begin()),
                 std::make_move_iterator(lines.end()));
    }
  }
  warnAboutDifferentFog(resolved, out);
  return out;
}

std::vector<std::unique_ptr<Sensor>> createSensors(const SensorContext& context) {
  for (const std::string& line : sensorWarnings(context.scenario.json()))
    logWarn(line);
  std::vector<std::unique_ptr<Sensor>> sensors;
  for (const SensorKind& kind : sensorKinds()) {
    const std::string path = fmt::format("{}.{}", kSensors, kind.key);
    const scenario::Json& list = context.scenario.at(path);
    for (std::size_t i = 0; i < list.size(); ++i)
      sensors.push_back(
          kind.create(SensorSetup{context, list[i], fmt::format("{}[{}]", path, i),
                                  static_cast<int>(i), static_cast<int>(list.size())}));
  }
  if (context.instances)
    sensors.insert(
        sensors.begin(),
        instanceTableSensor(context.instances,
                            datasetSection().read(context.scenario.json()).frame_period_ns));
  return sensors;
}

const scenario::Json* findSensorConfig(const scenario::Json& scenario, const std::string& name) {
  if (!scenario.contains(kSensors))
    return nullptr;
  for (const SensorKind& kind : sensorKinds()) {
    if (!scenario[kSensors].contains(kind.key))
      continue;
    for (const scenario::Json& item : scenario[kSensors][kind.key]) {
      try {
        if (readSensorName(item) == name)
          return &item;
      } catch (const scenario::Json::exception&) {  // not a resolved item: no name
      }
    }
  }
  return nullptr;
}

void addSensorsSection(scenario::Schema& schema) {
  std::vector<scenario::Param> kinds;
  for (const SensorKind& kind : sensorKinds())
    kinds.push_back(scenario::array(kind.key, kind.description, kind.declare()).maxItems(16));
  schema.add(scenario::object(kSensors, "Simulated sensors, a list per kind.", std::move(kinds)));
  schema.addCheck(checkSensorNames);
  schema.addCheck(checkFrameSynchronous);
  schema.addCheck(checkLidarsClearOfTheBody);
  schema.addCheck(checkPerceptionSensorsAboveTheRails);
  schema.addCheck([](const scenario::Json& resolved, std::vector<scenario::Problem>& problems) {
    for (const SensorKind& kind : sensorKinds()) {
      const scenario::Json& list = resolved.at(kSensors).at(kind.key);
      for (std::size_t i = 0; i < list.size(); ++i)
        kind.check(list[i], fmt::format("{}.{}[{}]", kSensors, kind.key, i), problems);
    }
  });
}

void checkSensorNames(const scenario::Json& resolved, std::vector<scenario::Problem>& problems) {
  std::map<std::string, std::string> names, files;  // name or file -> JSON path of its sensor
  for (const std::string& reserved : io::DatasetLayout::sequenceFiles())
    files[reserved] = "the dataset";
  // The manifest's entries of the dataset's own writers, beside the sensors'.
  names[FrameClock::kKind] = "the dataset's frame clock (times.txt and poses.txt)";
  names["instances"] = "the dataset's instance table (instances.csv)";
  for (const SensorKind& kind : sensorKinds()) {
    const scenario::Json& list = resolved.at(kSensors).at(kind.key);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string path = fmt::format("{}.{}[{}]", kSensors, kind.key, i);
      const std::string name = readSensorName(list[i]);
      if (!isIdentifier(name)) {
        problems.push_back(
            {path + ".name", fmt::format("'{}' is not a sensor name: use 1 to 64 lower-case "
                                         "letters, digits and '_', starting with a letter",
                                         messageValue(name))});
        continue;
      }
      if (const auto [it, fresh] = names.emplace(name, path); !fresh) {
        problems.push_back(
            {path + ".name", fmt::format("'{}' is already the name of {}", name, it->second)});
        continue;
      }
      for (const std::string& file : sensorFiles(kind.files, name)) {
        if (const auto [it, fresh] = files.emplace(file, path); !fresh)
          problems.push_back({path + ".name", fmt::format("'{}' would write {}, which {} writes",
                                                          name, file, it->second)});
      }
    }
  }
}

bool needsScene(const scenario::Json& resolved) {
  for (const SensorKind& kind : sensorKinds())
    if (kind.frame_synchronous && !resolved.at(kSensors).at(kind.key).empty())
      return true;
  return false;
}

bool hasSensors(const scenario::Json& resolved, std::string_view key) {
  return !resolved.at(kSensors).at(std::string(key)).empty();
}

void checkFrameSynchronous(const scenario::Json& resolved,
                           std::vector<scenario::Problem>& problems) {
  const TimeNs frame = datasetSection().read(resolved).frame_period_ns;
  for (const SensorKind& kind : sensorKinds()) {
    if (!kind.frame_synchronous)
      continue;
    const scenario::Json& list = resolved.at(kSensors).at(kind.key);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const TimeNs period = readSensorPeriod(list[i]);
      if (period != frame)
        problems.push_back({fmt::format("{}.{}[{}].period_ns", kSensors, kind.key, i),
                            fmt::format("is {} ns but must equal dataset.frame_period_ns ({} ns): "
                                        "KITTI pairs every scan and image with a line of "
                                        "times.txt and poses.txt",
                                        period, frame)});
    }
  }
}

}  // namespace trainsim::sim
