#pragma once

#include <memory>

#include "trainsim/scenario/param.hpp"
#include "trainsim/scenario/schema.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// sensors.gnss_receivers[]: position and velocity fixes with correlated errors, no fix in
/// tunnels, reacquisition delay after the portal.
scenario::Param declareGnss();
std::unique_ptr<Sensor> createGnss(const SensorSetup& setup);
void checkGnss(const scenario::Json& item, const std::string& path,
               std::vector<scenario::Problem>& problems);

/// sensors.odometers[]: wheel encoder pulses, distance and speed with scale error,
/// quantization, and slip (traction) / slide (braking) episodes.
scenario::Param declareOdometer();
std::unique_ptr<Sensor> createOdometer(const SensorSetup& setup);
void checkOdometer(const scenario::Json& item, const std::string& path,
                   std::vector<scenario::Problem>& problems);

/// sensors.balise_readers[]: balise groups along the track and one event per balise passed.
scenario::Param declareBaliseReader();
std::unique_ptr<Sensor> createBaliseReader(const SensorSetup& setup);
void checkBaliseReader(const scenario::Json& item, const std::string& path,
                       std::vector<scenario::Problem>& problems);

}  // namespace trainsim::sim
