#pragma once

// What every sensor kind declares first — its name, its period and (most kinds) its mount —
// bound once here, so that each convention is declared and read in one place.

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "trainsim/core/frames.hpp"
#include "trainsim/core/time.hpp"
#include "trainsim/scenario/binding.hpp"

namespace trainsim::sim {

/// A sensor's mount as the scenario gives it: position relative to the body reference point
/// and attitude (roll, pitch, yaw; by trainsim::attitude, pitch positive nose-up), body axes.
struct MountParams {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;

  Mount mount() const { return {position_m, attitude(yaw_rad, pitch_rad, roll_rad)}; }
};

/// The fields every sensor has; a kind's config struct holds them as `basics`, with the kind's
/// defaults as its member initialiser.
struct SensorBasics {
  std::string name;
  TimeNs period_ns = 0;
  MountParams mount;
};

/// How a kind declares its basics.
struct BasicsSpec {
  const char* files;  ///< the files it writes, for the name's description
  TimeNs min_period_ns, max_period_ns;
  const char* period_description;
  const char* mount_description;  ///< nullptr: the kind has no mount
};

/// The binding of the basics: `name` (unique across all sensors and safe as a file name,
/// checked by the schema; unnamed items of a list are `base`, `base_1`, … by position),
/// `period_ns` (a multiple of trajectory.sample_period_ns) and `mount` (x_m, y_m, z_m,
/// roll_deg, pitch_deg, yaw_deg). Embed it: b.embed(&Config::basics, sensorBasics(spec)).
scenario::Binding<SensorBasics> sensorBasics(const BasicsSpec& spec);

/// The name of a resolved sensor item (for checks across sensors and the studio).
std::string readSensorName(const scenario::Json& item);
/// The period of a resolved sensor item.
TimeNs readSensorPeriod(const scenario::Json& item);
/// The mount of a resolved sensor item of a kind with a mount.
Mount readMount(const scenario::Json& item);
/// The JSON path of the mount of the sensor item at `item_path`, for messages.
std::string mountPath(const std::string& item_path);

/// The files a sensor writes in the sequence folder, as patterns with "{}" for its name: the
/// one list both the schema's file-clash check and the sensor's own outputs() use. The first
/// file is the sensor's readings.
inline constexpr const char* kReadingsCsv[] = {"{}.csv"};
inline constexpr const char* kImuCsvs[] = {"{}.csv", "{}_truth.csv"};
std::vector<std::string> sensorFiles(std::span<const char* const> patterns,
                                     const std::string& name);

/// How far along the track a body point at `mount` lies ahead of the front bogie pivot (the
/// point whose chainage and distance the trajectory reports), from the resolved scenario's
/// train section. Negative: behind it.
double aheadOfFrontPivot(const scenario::Json& scenario, const Mount& mount);

}  // namespace trainsim::sim
