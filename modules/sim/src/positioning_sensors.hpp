#pragma once

#include <memory>

#include "trainsim/scenario/param.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// sensors.gnss_receivers[]: position and velocity fixes with correlated errors, no fix in
/// tunnels, reacquisition delay after the portal.
scenario::Param declareGnss();
std::unique_ptr<Sensor> createGnss(const SensorSetup& setup);

/// sensors.odometers[]: wheel encoder pulses, distance and speed with scale error,
/// quantization, and slip (traction) / slide (braking) episodes.
scenario::Param declareOdometer();
std::unique_ptr<Sensor> createOdometer(const SensorSetup& setup);

/// sensors.balise_readers[]: balise groups along the track and one event per balise passed.
scenario::Param declareBaliseReader();
std::unique_ptr<Sensor> createBaliseReader(const SensorSetup& setup);

}  // namespace trainsim::sim
