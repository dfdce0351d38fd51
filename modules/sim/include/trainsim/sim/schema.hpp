#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/scenario/schema.hpp"

namespace trainsim::sim {

/// The complete scenario schema: the general sections declared here plus every section the
/// pipeline's modules and the sensor registry declare. Built once.
const scenario::Schema& scenarioSchema();

/// The scenario's geodetic anchor (`geodetic_origin` of a resolved scenario document).
GeodeticAnchor geodeticAnchor(const scenario::Json& scenario);

/// The built-in default scenario (configs/default.json, embedded in the binary at build time).
std::string_view defaultScenarioText();

/// Loads, validates and resolves a scenario: from `path` ("-" for standard input), or the
/// built-in default when `path` is empty. `seed_override`, when given, replaces the
/// scenario's seed. Throws ConfigError (InvalidScenario lists every problem).
scenario::Scenario loadScenario(const std::string& path,
                                std::optional<std::uint64_t> seed_override = std::nullopt);

/// Validates and resolves a scenario document; relative file names in it (route.waypoints_file)
/// are taken relative to `base_dir` when that is not empty. Throws InvalidScenario.
scenario::Scenario resolveScenario(scenario::Json input, const std::string& base_dir,
                                   const std::string& source);

}  // namespace trainsim::sim
