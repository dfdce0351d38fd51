#include "trainsim/sim/schema.hpp"

#include <filesystem>
#include <optional>

#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::embedded {
extern const std::string_view default_scenario_json;
}  // namespace trainsim::embedded

namespace trainsim::sim {
namespace {

using scenario::array;
using scenario::boolean;
using scenario::choice;
using scenario::integer;
using scenario::number;
using scenario::object;
using scenario::Param;
using scenario::Schema;

constexpr double kMaxSafeInteger = 9007199254740991.0;  // 2^53 - 1, exact in every JSON reader

Param special(std::string key, std::string what, double probability, double lo, double hi) {
  return object(
      key, "Random " + what + "s, placed on straights",
      {number("probability", probability, "", "Probability that a straight stretch holds a " + what)
           .range(0, 1),
       number("length_min_m", lo, "m", "Shortest " + what).range(1, 1e5),
       number("length_max_m", hi, "m", "Longest " + what).range(1, 1e5)});
}

void addRouteSections(Schema& s) {
  s.add(object(
      "route", "Where the main track comes from and how it is laid out.",
      {choice("source", "generated", {"generated", "waypoints", "blocks"},
              "Random route from route.generator, a waypoint CSV (route.waypoints_file), or the "
              "block list route.blocks"),
       scenario::string("waypoints_file", "",
                        "CSV of waypoints (n_m,e_m,d_m or latitude_deg,longitude_deg,height_m; "
                        "optional radius_m, vertical_radius_m, block); relative paths are relative "
                        "to the scenario file"),
       number("waypoint_radius_max_m", 50000, "m",
              "Largest arc radius chosen at a waypoint that gives none")
           .range(50, 1e6),
       choice("transition_shape", "clothoid", {"clothoid", "bloss"},
              "Transition curve and matching cant ramp (clothoid: linear; Bloss: cubic)"),
       choice("cant_rotation", "centre", {"centre", "inner_rail"},
              "Axis the cant turns the track about: the centreline, or the low rail (the "
              "centreline rises by D/2, with a vertical kink at the ends of linear ramps)"),
       boolean("station_stops", true, "The train stops at every station"),
       number("station_dwell_s", 30, "s", "Dwell time at a station stop").range(0, 3600),
       object(
           "generator", "Seeded random route (route.source = generated).",
           {number("length_m", 6000, "m", "Route length (horizontal chainage)").range(500, 2e6),
            number("radius_min_m", 0, "m",
                   "Smallest arc radius; 0 or anything below the design minimum uses the "
                   "minimum radius for design.design_speed_km_h")
                .range(0, 1e6),
            number("radius_max_m", 4000, "m", "Largest arc radius").range(100, 1e6),
            number("curve_share", 0.4, "", "Fraction of the length in curves").range(0, 0.95),
            number("arc_length_min_m", 150, "m", "Shortest circular arc").range(1, 1e5),
            number("arc_length_max_m", 800, "m", "Longest circular arc").range(1, 1e5),
            special("station", "station", 0.3, 250, 250),
            special("tunnel", "tunnel", 0.15, 200, 800), special("bridge", "bridge", 0.15, 50, 300),
            number("grade_max_permille", 12.5, "permille",
                   "Steepest grade drawn (at most design.max_grade_permille)")
                .range(0, 100),
            number("grade_length_min_m", 600, "m", "Shortest distance between grade changes")
                .range(10, 1e5),
            number("grade_length_max_m", 2500, "m", "Longest distance between grade changes")
                .range(10, 1e6)}),
       array(
           "blocks",
           "The main track block by block, starting east at the origin (route.source = blocks).",
           object(
               "", "One block of the main track.",
               {choice("type", "straight", {"straight", "curve", "station", "tunnel", "bridge"},
                       "What the block is"),
                number("length_m", 500, "m",
                       "Length of a straight-like block; for a curve, of its circular arc alone")
                    .range(0, 1e6),
                number("radius_m", 1500, "m", "Curves: radius of the circular arc").range(10, 1e6),
                choice("direction", "left", {"left", "right"}, "Curves: direction of the turn"),
                number("transition_m", -1, "m",
                       "Curves: length of each transition; -1 chooses the design minimum (at "
                       "least 20 m, in 5 m steps)")
                    .range(-1, 10000),
                number("cant_mm", -1, "mm",
                       "Curves: applied cant; -1 lets the design rules choose it")
                    .range(-1, 250),
                number("grade_permille", 0, "permille",
                       "Grade from the start of this block on (positive climbs)")
                    .range(-100, 100)}))}));
  s.add(object(
      "design", "Design rules the route is generated to and checked against (design_report.json).",
      {number("design_speed_km_h", 160, "km/h", "Line speed the alignment is designed for")
           .range(20, 400),
       number("max_cant_mm", 160, "mm", "Largest applied cant D").range(0, 200),
       number("max_cant_deficiency_mm", 130, "mm", "Largest cant deficiency I").range(1, 300),
       number("max_cant_rate_mm_s", 50, "mm/s", "Largest rate of change of cant dD/dt")
           .range(1, 200),
       number("max_deficiency_rate_mm_s", 55, "mm/s",
              "Largest rate of change of cant deficiency dI/dt (lateral jerk)")
           .range(1, 200),
       number("max_cant_gradient_mm_m", 2.25, "mm/m", "Steepest cant ramp dD/ds").range(0.1, 10),
       number("min_element_duration_s", 1.8, "s",
              "Straights and arcs last at least this long at design speed (0.5 V m, V in km/h)")
           .range(0, 60),
       number("max_grade_permille", 12.5, "permille", "Steepest grade").range(0, 100),
       number("max_vertical_accel_m_s2", 0.2, "m/s^2",
              "Vertical acceleration on vertical curves: R_v >= v^2 / a_v")
           .range(0.01, 2),
       number("station_max_grade_permille", 2.5, "permille", "Steepest grade at a platform")
           .range(0, 100),
       number("station_max_cant_mm", 60, "mm", "Largest cant at a platform").range(0, 200),
       number("station_speed_km_h", 60, "km/h", "Speed limit through stations").range(5, 400),
       number("tunnel_speed_km_h", 120, "km/h", "Speed limit in tunnels").range(5, 400),
       number("bridge_speed_km_h", 120, "km/h", "Speed limit on bridges").range(5, 400)}));
  s.add(object(
      "layout", "Tracks beside the main track (railroad.json).",
      {boolean("double_track", true, "Second track on the right of the main track"),
       number("track_centre_distance_m", 4.0, "m", "Distance between neighbouring track centres")
           .range(3.0, 10.0),
       number("polyline_spacing_m", 2.0, "m", "Largest spacing of railroad.json polylines")
           .range(0.1, 100),
       object(
           "auxiliary", "Auxiliary tracks: entering, parallel and outgoing parts.",
           {number("probability", 0.3, "", "Probability per eligible straight stretch").range(0, 1),
            number("parallel_min_m", 300, "m", "Shortest parallel part").range(10, 1e5),
            number("parallel_max_m", 800, "m", "Longest parallel part").range(10, 1e5),
            number("turnout_probability", 0.5, "",
                   "Probability that an end joins the next track through a turnout (else it "
                   "is a dead end)")
                .range(0, 1),
            choice("turnout", "190-1:9", {"190-1:9", "500-1:12"},
                   "Turnout type (radius-crossing ratio)"),
            number("dead_end_length_m", 40, "m", "Length of a dead-end straight").range(1, 1e4),
            choice("side", "either", {"left", "right", "either"},
                   "Side of the main track (right: beyond the double track)")})}));
  s.add(object(
      "train", "The train: longitudinal limits, dynamics and the body on its bogies.",
      {number("max_accel_m_s2", 0.8, "m/s^2", "Largest acceleration").range(0.01, 5),
       number("max_brake_m_s2", 0.6, "m/s^2", "Service braking deceleration").range(0.01, 5),
       number("max_jerk_m_s3", 0.6, "m/s^3", "Largest longitudinal jerk").range(0.01, 10),
       number("length_m", 100, "m", "Train length: restrictions hold until the rear clears them")
           .range(1, 2000),
       number("bogie_spacing_m", 17.5, "m", "Distance between the front car's bogie pivots")
           .range(1, 40),
       object("reference_point",
              "Body point whose pose is reported (body axes x fwd, y left, z up; origin midway "
              "between the bogie pivots at top of rail)",
              {number("x_m", 0, "m", "Forward").range(-100, 100),
               number("y_m", 0, "m", "Left").range(-10, 10),
               number("z_m", 0, "m", "Up").range(-10, 10)}),
       object(
           "dynamics", "Optional traction and running resistance limiting acceleration.",
           {boolean("enabled", false, "Limit acceleration by traction, Davis resistance and grade"),
            number("mass_kg", 260e3, "kg", "Train mass").range(1e3, 1e8),
            number("rotating_mass_factor", 1.05, "", "1 + rho").range(1, 2),
            number("davis_a_n", 2288, "N", "Davis A").range(0, 1e7),
            number("davis_b_n_s_m", 68.33, "N s/m", "Davis B").range(0, 1e7),
            number("davis_c_n_s2_m2", 7.75, "N s^2/m^2", "Davis C").range(0, 1e7),
            number("max_traction_n", 242e3, "N", "Starting tractive effort").range(0, 1e8),
            number("max_power_w", 1.8e6, "W", "Traction power (effort falls as P/v)")
                .range(1, 1e9)})}));
  s.addCheck([](const scenario::Json& r, std::vector<scenario::Problem>& problems) {
    const auto& route = r["route"];
    if (route["source"] == "blocks" && route["blocks"].empty())
      problems.push_back({"route.blocks",
                          "must list at least one block when route.source is "
                          "\"blocks\""});
    for (std::size_t i = 0; i < route["blocks"].size(); ++i) {
      const auto& b = route["blocks"][i];
      const std::string at = "route.blocks[" + std::to_string(i) + "]";
      if (b["type"] == "curve" && b["length_m"].get<double>() <= 0.0 &&
          b["transition_m"].get<double>() == 0.0)
        problems.push_back({at + ".length_m", "a curve needs an arc or transitions"});
      if (b["type"] != "curve" && b["length_m"].get<double>() <= 0.0)
        problems.push_back({at + ".length_m",
                            "must be positive for a " + b["type"].get<std::string>() + " block"});
    }
    if (route["source"] == "waypoints" && route["waypoints_file"].get<std::string>().empty())
      problems.push_back({"route.waypoints_file",
                          "must name a CSV file when route.source is "
                          "\"waypoints\""});
    const auto& g = route["generator"];
    auto order = [&](const scenario::Json& o, const char* lo, const char* hi, std::string path) {
      if (o[lo].get<double>() > o[hi].get<double>())
        problems.push_back({path + "." + lo, std::string("must not exceed ") + hi});
    };
    order(g, "arc_length_min_m", "arc_length_max_m", "route.generator");
    order(g, "grade_length_min_m", "grade_length_max_m", "route.generator");
    for (const char* k : {"station", "tunnel", "bridge"})
      order(g[k], "length_min_m", "length_max_m", std::string("route.generator.") + k);
    if (g["station"]["probability"].get<double>() + g["tunnel"]["probability"].get<double>() +
            g["bridge"]["probability"].get<double>() >
        1.0)
      problems.push_back({"route.generator",
                          "station, tunnel and bridge probabilities add up to "
                          "more than 1"});
    if (g["grade_max_permille"].get<double>() > r["design"]["max_grade_permille"].get<double>())
      problems.push_back(
          {"route.generator.grade_max_permille", "must not exceed design.max_grade_permille"});
    order(r["layout"]["auxiliary"], "parallel_min_m", "parallel_max_m", "layout.auxiliary");
    if (r["train"]["bogie_spacing_m"].get<double>() > r["train"]["length_m"].get<double>())
      problems.push_back({"train.bogie_spacing_m", "must not exceed train.length_m"});
  });
}

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

  addRouteSections(s);

  std::vector<Param> kinds;
  for (const SensorKind& kind : sensorKinds()) {
    kinds.push_back(array(kind.key, kind.description, kind.declare()));
  }
  s.add(object("sensors", "Simulated sensors, a list per kind.", std::move(kinds)));
  s.addCheck(checkSensorNames);
  return s;
}

}  // namespace

const Schema& scenarioSchema() {
  static const Schema schema = buildSchema();
  return schema;
}

GeodeticAnchor geodeticAnchor(const scenario::Json& scenario) {
  const scenario::Json& o = scenario.at("geodetic_origin");
  return GeodeticAnchor({o.at("latitude_deg").get<double>(), o.at("longitude_deg").get<double>(),
                         o.at("height_m").get<double>()});
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
  // A relative waypoint file is relative to the scenario file that names it.
  const bool from_file = !path.empty() && path != "-";
  return resolveScenario(std::move(input),
                         from_file ? std::filesystem::path(path).parent_path().string() : "",
                         source);
}

scenario::Scenario resolveScenario(scenario::Json input, const std::string& base_dir,
                                   const std::string& source) {
  if (!base_dir.empty() && input.is_object() && input.contains("route") &&
      input["route"].is_object() && input["route"].contains("waypoints_file") &&
      input["route"]["waypoints_file"].is_string()) {
    const std::filesystem::path file = input["route"]["waypoints_file"].get<std::string>();
    if (!file.empty() && file.is_relative())
      input["route"]["waypoints_file"] =
          (std::filesystem::path(base_dir) / file).lexically_normal().string();
  }
  return scenario::Scenario::resolve(input, scenarioSchema(), source);
}

}  // namespace trainsim::sim
