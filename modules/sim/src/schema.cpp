#include "trainsim/sim/schema.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <optional>

#include "trainsim/sim/config.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::embedded {
extern const std::string_view default_scenario_json;
}  // namespace trainsim::embedded

namespace trainsim::sim {
namespace {

using scenario::Schema;

// The scenario's top-level sections, in document order: one line per section. A section's
// declaration lives beside its binding (config.hpp, sections/*.cpp); adding one is one
// binding plus its line here (and its line in the plan's stage table if a stage reads it).
constexpr void (*kSections[])(Schema&) = {
    [](Schema& s) {
      s.add(scenario::string("description", "", "Free text describing the scenario"));
    },
    [](Schema& s) { s.add(scenario::seedParam()); },
    [](Schema& s) { geodeticOriginSection().addTo(s); },
    [](Schema& s) { trajectorySection().addTo(s); },
    [](Schema& s) { datasetSection().addTo(s); },
    [](Schema& s) { routeSection().addTo(s); },
    [](Schema& s) { designSection().addTo(s); },
    [](Schema& s) { layoutSection().addTo(s); },
    [](Schema& s) { trainSection().addTo(s); },
    [](Schema& s) { terrainSection().addTo(s); },
    [](Schema& s) {
      assetsSection().addTo(s);
      // The catenary under a tunnel's crown: the lining's roof over a track off the tube's
      // centre lies up to half a metre lower, and the messenger keeps 1.1 m (the least system
      // height in tunnels, sensors-reference.md 5.3) over the wire and 0.2 m under the roof.
      s.addCheck([](const scenario::Json& resolved, std::vector<scenario::Problem>& problems) {
        const environment::AssetParams a = assetsSection().read(resolved);
        const terrain::TerrainParams t = terrainSection().read(resolved);
        if (const double least = a.contact_height_m + 1.1 + 0.2 + 0.5;
            a.catenary && t.tunnel_crown_m < least - 1e-9)
          problems.push_back(
              {terrainSection().path(&terrain::TerrainParams::tunnel_crown_m),
               fmt::format("is {:g} m but the catenary needs at least {:g} m in a tunnel ({} {:g} "
                           "m, 1.1 m of system height, 0.2 m under the lining, 0.5 m for a track "
                           "off the tube's centre); or set {} false",
                           t.tunnel_crown_m, least,
                           assetsSection().path(&environment::AssetParams::contact_height_m),
                           a.contact_height_m,
                           assetsSection().path(&environment::AssetParams::catenary))});
      });
    },
    [](Schema& s) { objectsSection().addTo(s); },
    [](Schema& s) { addSensorsSection(s); },
};

Schema buildSchema() {
  Schema s;
  for (const auto add : kSections)
    add(s);
  return s;
}

}  // namespace

const Schema& scenarioSchema() {
  static const Schema schema = buildSchema();
  return schema;
}

GeodeticAnchor geodeticAnchor(const scenario::Json& scenario) {
  return GeodeticAnchor(geodeticOriginSection().read(scenario));
}

std::string_view defaultScenarioText() {
  return embedded::default_scenario_json;
}

scenario::Scenario loadScenario(const std::string& path, std::optional<std::uint64_t> seed) {
  const std::string source = path.empty()  ? "<built-in default scenario>"
                             : path == "-" ? "<stdin>"
                                           : path;
  const std::string text =
      path.empty() ? std::string(defaultScenarioText()) : scenario::readScenarioText(path);
  scenario::Json input = scenario::parseJson(text, source);
  if (seed)
    scenario::overrideSeed(input, *seed);
  // A relative waypoint file is relative to the scenario file that names it.
  const bool from_file = !path.empty() && path != "-";
  return resolveScenario(std::move(input),
                         from_file ? std::filesystem::path(path).parent_path().string() : "",
                         source);
}

scenario::Scenario resolveScenario(scenario::Json input, const std::string& base_dir,
                                   const std::string& source) {
  // The waypoint file's pointer, from the binding (no key spelled here).
  const scenario::Json::json_pointer file_at =
      scenario::pointerFromPath(routeSection().path(&RouteConfig::waypoints_file));
  if (!base_dir.empty() && input.is_object() && input.contains(file_at) &&
      input[file_at].is_string()) {
    const std::filesystem::path file = input[file_at].get<std::string>();
    if (!file.empty() && file.is_relative())
      input[file_at] = (std::filesystem::path(base_dir) / file).lexically_normal().string();
  }
  return scenario::Scenario::resolve(input, scenarioSchema(), source);
}

}  // namespace trainsim::sim
