#pragma once

// Declarations and readers shared by every sensor kind, so that each convention is declared
// and read in one place: the sensor's name, its period and its mount.

#include <span>
#include <string>
#include <vector>

#include "trainsim/core/frames.hpp"
#include "trainsim/core/time.hpp"
#include "trainsim/scenario/param.hpp"

namespace trainsim::sim {

/// `name`: unique across all sensors and safe as a file name (checked by the schema); when
/// omitted, items of a list are named `base`, `base_1`, `base_2`, … by position.
scenario::Param declareSensorName(const std::string& base, const std::string& files);
std::string readSensorName(const scenario::Json& config);

/// The files a sensor writes in the sequence folder, as patterns with "{}" for its name: the
/// one list both the schema's file-clash check and the sensor's own outputs() use. The first
/// file is the sensor's readings.
inline constexpr const char* kReadingsCsv[] = {"{}.csv"};
inline constexpr const char* kImuCsvs[] = {"{}.csv", "{}_truth.csv"};
std::vector<std::string> sensorFiles(std::span<const char* const> patterns,
                                     const std::string& name);

/// `period_ns`: a multiple of trajectory.sample_period_ns within [minimum, maximum].
scenario::Param declarePeriod(TimeNs default_ns, TimeNs minimum_ns, TimeNs maximum_ns,
                              const std::string& description);
TimeNs readPeriod(const scenario::Json& config);

/// Default mount values (body axes, metres and degrees).
struct MountDefaults {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
};
/// `mount`: position relative to the body reference point and attitude (roll, pitch, yaw in
/// degrees, by trainsim::attitude: pitch positive nose-up), in body axes.
scenario::Param declareMount(const std::string& description, MountDefaults defaults = {});
Mount readMount(const scenario::Json& config);

/// How far along the track a body point at `mount` lies ahead of the front bogie pivot (the
/// point whose chainage and distance the trajectory reports), from the resolved scenario's
/// train.reference_point.x_m and train.bogie_spacing_m. Negative: behind it.
double aheadOfFrontPivot(const scenario::Json& scenario, const Mount& mount);

}  // namespace trainsim::sim
