#include "trainsim/sim/schema.hpp"

#include <optional>

#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::embedded {
extern const std::string_view default_scenario_json;
}  // namespace trainsim::embedded

namespace trainsim::sim {
namespace {

using scenario::array;
using scenario::integer;
using scenario::number;
using scenario::object;
using scenario::Param;
using scenario::Schema;

constexpr double kMaxSafeInteger = 9007199254740991.0;  // 2^53 - 1, exact in every JSON reader

Schema buildSchema() {
  Schema s;
  s.add(scenario::string("description", "", "Free text describing the scenario"));
  s.add(integer("seed", 1, "",
                "Master seed; every random stream is keyed by (seed, stream name, index)")
            .range(0, kMaxSafeInteger));
  s.add(object(
      "geodetic_origin",
      "Where the scenario's local frame sits on Earth. The world frame is ENU (x east, "
      "y north, z up) tangent to the WGS-84 ellipsoid at this point.",
      {number("latitude_deg", 43.7228, "deg", "Geodetic latitude of the origin").range(-90, 90),
       number("longitude_deg", 10.3966, "deg", "Geodetic longitude of the origin").range(-180, 180),
       number("height_m", 50.0, "m", "Ellipsoidal height of the origin").range(-500, 9000)}));
  s.add(object("trajectory", "Ground-truth trajectory sampling (the movement system's clock).",
               {integer("sample_period_ns", 10'000'000, "ns",
                        "Trajectory sample period T_S; every sensor period is a multiple of it")
                    .range(100'000, 1'000'000'000)}));
  s.add(object("dataset", "Dataset layout and the frame clock of the visual sensors.",
               {integer("sequence", 0, "", "KITTI sequence number: output goes to sequences/NN")
                    .range(0, 99),
                integer("frame_period_ns", 100'000'000, "ns",
                        "Period of dataset frames (times.txt, poses.txt, LiDAR scans, images)")
                    .range(1'000'000, 60'000'000'000)
                    .multipleOf("trajectory.sample_period_ns")}));

  std::vector<Param> kinds;
  for (const SensorKind& kind : sensorKinds()) {
    kinds.push_back(array(kind.key, kind.description, kind.declare()));
  }
  s.add(object("sensors", "Simulated sensors, a list per kind.", std::move(kinds)));
  return s;
}

}  // namespace

const Schema& scenarioSchema() {
  static const Schema schema = buildSchema();
  return schema;
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
  if (seed && input.is_object()) {
    input["seed"] = *seed;
  }
  return scenario::Scenario::resolve(input, scenarioSchema(), source);
}

}  // namespace trainsim::sim
