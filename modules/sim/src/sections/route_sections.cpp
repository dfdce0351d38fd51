// The `route` and `design` sections: declarations bound to RouteConfig and track::DesignRules.

#include "trainsim/sim/config.hpp"

namespace trainsim::sim {
namespace {

using scenario::Binding;
using scenario::Problem;
using scenario::Sentinel;
namespace units = scenario::units;
using track::BlockSpec;
using track::RouteGeneratorParams;
using track::SpecialBlockParams;

constexpr scenario::Unit kM = units::si("m");
constexpr scenario::Unit kS = units::si("s");

Binding<SpecialBlockParams> specialBinding(const std::string& what) {
  Binding<SpecialBlockParams> b;
  b.number("probability", &SpecialBlockParams::probability, units::kNone,
           "Probability that a straight stretch holds a " + what)
      .range(0, 1);
  b.number("length_min_m", &SpecialBlockParams::length_min_m, kM, "Shortest " + what).range(1, 1e5);
  b.number("length_max_m", &SpecialBlockParams::length_max_m, kM, "Longest " + what).range(1, 1e5);
  b.notAbove(&SpecialBlockParams::length_min_m, &SpecialBlockParams::length_max_m);
  return b;
}

const Binding<RouteGeneratorParams>& generatorBinding() {
  static const Binding<SpecialBlockParams> station = specialBinding("station"),
                                           tunnel = specialBinding("tunnel"),
                                           bridge = specialBinding("bridge");
  static const Binding<RouteGeneratorParams> binding = [] {
    using G = RouteGeneratorParams;
    Binding<G> b;
    b.number("length_m", &G::length_m, kM, "Route length (horizontal chainage)").range(500, 2e6);
    b.number("radius_min_m", &G::radius_min_m, kM,
             "Smallest arc radius; 0 or anything below the design minimum uses the minimum "
             "radius for design.design_speed_km_h")
        .range(0, 1e6);
    b.number("radius_max_m", &G::radius_max_m, kM, "Largest arc radius").range(100, 1e6);
    b.number("curve_share", &G::curve_share, units::kNone, "Fraction of the length in curves")
        .range(0, 0.95);
    b.number("arc_length_min_m", &G::arc_length_min_m, kM, "Shortest circular arc").range(1, 1e5);
    b.number("arc_length_max_m", &G::arc_length_max_m, kM, "Longest circular arc").range(1, 1e5);
    b.object("station", &G::station, station, "Random stations, placed on straights");
    b.object("tunnel", &G::tunnel, tunnel, "Random tunnels, placed on straights");
    b.object("bridge", &G::bridge, bridge, "Random bridges, placed on straights");
    b.number("grade_max_permille", &G::grade_max, units::kPermille,
             "Steepest grade drawn (at most design.max_grade_permille)")
        .range(0, 100);
    b.number("grade_length_min_m", &G::grade_length_min_m, kM,
             "Shortest distance between grade changes")
        .range(10, 1e5);
    b.number("grade_length_max_m", &G::grade_length_max_m, kM,
             "Longest distance between grade changes")
        .range(10, 1e6);
    b.notAbove(&G::radius_min_m, &G::radius_max_m);
    b.notAbove(&G::arc_length_min_m, &G::arc_length_max_m);
    b.notAbove(&G::grade_length_min_m, &G::grade_length_max_m);
    b.check([](const G& g, const scenario::FieldPaths<G>& at, std::vector<Problem>& out) {
      if (g.station.probability + g.tunnel.probability + g.bridge.probability > 1.0)
        out.push_back(
            {at.prefix(), "station, tunnel and bridge probabilities add up to more than 1"});
    });
    return b;
  }();
  return binding;
}

const Binding<BlockSpec>& blockBinding() {
  static const Binding<BlockSpec> binding = [] {
    Binding<BlockSpec> b;
    b.choice("type", &BlockSpec::type, "What the block is", {track::BlockType::kSwitch});
    b.number("length_m", &BlockSpec::length_m, kM,
             "Length of a straight-like block; for a curve, of its circular arc alone")
        .range(0, 1e6);
    b.number("radius_m", &BlockSpec::radius_m, kM, "Curves: radius of the circular arc")
        .range(10, 1e6);
    b.choice("direction", &BlockSpec::direction, "Curves: direction of the turn");
    b.number("transition_m", &BlockSpec::transition_m, kM,
             "Curves: length of each transition; -1 chooses the design minimum (at least 20 m, "
             "in 5 m steps)",
             Sentinel{-1.0, -1.0})
        .range(-1, 10000);
    b.number("cant_mm", &BlockSpec::cant_m, units::kMillimetre,
             "Curves: applied cant; -1 lets the design rules choose it", Sentinel{-1.0, -1.0})
        .range(-1, 250);
    b.number("grade_permille", &BlockSpec::grade, units::kPermille,
             "Grade from the start of this block on (positive climbs)")
        .range(-100, 100);
    b.check([](const BlockSpec& s, const scenario::FieldPaths<BlockSpec>& at,
               std::vector<Problem>& out) {
      const bool curve = s.type == track::BlockType::kCurve;
      if (curve && s.length_m <= 0.0 && s.transition_m == 0.0)
        out.push_back({at(s.length_m), "a curve needs an arc or transitions"});
      if (!curve && s.length_m <= 0.0)
        out.push_back(
            {at(s.length_m), "must be positive for a " + std::string(nameOf(s.type)) + " block"});
    });
    return b;
  }();
  return binding;
}

}  // namespace

scenario::Json routeBlockJson(const track::BlockSpec& block) {
  return blockBinding().write(block);
}

const scenario::Section<RouteConfig>& routeSection() {
  static const scenario::Section<RouteConfig> section = [] {
    scenario::Section<RouteConfig> s{
        "route", "Where the main track comes from and how it is laid out.", {}, {}};
    Binding<RouteConfig>& b = s.binding;
    b.choice("source", &RouteConfig::source,
             "Random route from route.generator, a waypoint CSV (route.waypoints_file), or the "
             "block list route.blocks");
    b.string("waypoints_file", &RouteConfig::waypoints_file,
             "CSV of waypoints (n_m,e_m,d_m or latitude_deg,longitude_deg,height_m; optional "
             "radius_m, vertical_radius_m, block); relative paths are relative to the scenario "
             "file");
    b.number("waypoint_radius_max_m",
             scenario::nested(&RouteConfig::waypoints, &track::WaypointParams::radius_max_m), kM,
             "Largest arc radius chosen at a waypoint that gives none")
        .range(50, 1e6);
    b.choice("transition_shape",
             scenario::nested(&RouteConfig::options, &track::RouteOptions::transition_shape),
             "Transition curve and matching cant ramp (clothoid: linear; Bloss: cubic)");
    b.choice("cant_rotation",
             scenario::nested(&RouteConfig::options, &track::RouteOptions::cant_rotation),
             "Axis the cant turns the track about: the centreline, or the low rail (the centreline "
             "rises by D/2, with a vertical kink at the ends of linear ramps)");
    b.boolean("station_stops",
              scenario::nested(&RouteConfig::options, &track::RouteOptions::station_stops),
              "The train stops at every station");
    b.number("station_dwell_s",
             scenario::nested(&RouteConfig::options, &track::RouteOptions::station_dwell_s), kS,
             "Dwell time at a station stop")
        .range(0, 3600);
    b.object("generator", &RouteConfig::generator, generatorBinding(),
             "Seeded random route (route.source = generated).");
    b.array("blocks", &RouteConfig::blocks, blockBinding(), "One block of the main track.",
            "The main track block by block, starting east at the origin (route.source = "
            "blocks).")
        .maxItems(100'000);
    b.check([](const RouteConfig& c, const scenario::FieldPaths<RouteConfig>& at,
               std::vector<Problem>& out) {
      const std::string source = at(c.source) + " is \"" + std::string(nameOf(c.source)) + "\"";
      if (c.source == RouteSource::kBlocks && c.blocks.empty())
        out.push_back({at(c.blocks), "must list at least one block when " + source});
      if (c.source == RouteSource::kWaypoints && c.waypoints_file.empty())
        out.push_back({at(c.waypoints_file), "must name a CSV file when " + source});
    });
    s.cross_checks.push_back([](const RouteConfig& c, const scenario::Json& resolved,
                                std::vector<Problem>& out) {
      const track::DesignRules rules = designSection().read(resolved);
      if (c.generator.grade_max > rules.max_grade)
        out.push_back({routeSection().path(scenario::nested(&RouteConfig::generator,
                                                            &RouteGeneratorParams::grade_max)),
                       "must not exceed " + designSection().path(&track::DesignRules::max_grade)});
    });
    return s;
  }();
  return section;
}

const scenario::Section<track::DesignRules>& designSection() {
  static const scenario::Section<track::DesignRules> section = [] {
    using R = track::DesignRules;
    scenario::Section<R> s{
        "design",
        "Design rules the route is generated to and checked against (design_report.json).",
        {},
        {}};
    Binding<R>& b = s.binding;
    b.number("design_speed_km_h", &R::design_speed_m_s, units::kKilometrePerHour,
             "Line speed the alignment is designed for")
        .range(20, 400);
    b.number("max_cant_mm", &R::max_cant_m, units::kMillimetre, "Largest applied cant D")
        .range(0, 200);
    b.number("max_cant_deficiency_mm", &R::max_cant_deficiency_m, units::kMillimetre,
             "Largest cant deficiency I")
        .range(1, 300);
    b.number("max_cant_rate_mm_s", &R::max_cant_rate_m_s, units::kMillimetrePerSecond,
             "Largest rate of change of cant dD/dt")
        .range(1, 200);
    b.number("max_deficiency_rate_mm_s", &R::max_deficiency_rate_m_s, units::kMillimetrePerSecond,
             "Largest rate of change of cant deficiency dI/dt (lateral jerk)")
        .range(1, 200);
    b.number("max_cant_gradient_mm_m", &R::max_cant_gradient, units::kMillimetrePerMetre,
             "Steepest cant ramp dD/ds")
        .range(0.1, 10);
    b.number("min_element_duration_s", &R::min_element_duration_s, kS,
             "Straights and arcs last at least this long at design speed (0.5 V m, V in km/h)")
        .range(0, 60);
    b.number("max_grade_permille", &R::max_grade, units::kPermille, "Steepest grade").range(0, 100);
    b.number("max_vertical_accel_m_s2", &R::max_vertical_accel_m_s2, units::si("m/s^2"),
             "Vertical acceleration on vertical curves: R_v >= v^2 / a_v")
        .range(0.01, 2);
    b.number("station_max_grade_permille", &R::station_max_grade, units::kPermille,
             "Steepest grade at a platform")
        .range(0, 100);
    b.number("station_max_cant_mm", &R::station_max_cant_m, units::kMillimetre,
             "Largest cant at a platform")
        .range(0, 200);
    b.number("station_speed_km_h", &R::station_speed_m_s, units::kKilometrePerHour,
             "Speed limit through stations")
        .range(5, 400);
    b.number("tunnel_speed_km_h", &R::tunnel_speed_m_s, units::kKilometrePerHour,
             "Speed limit in tunnels")
        .range(5, 400);
    b.number("bridge_speed_km_h", &R::bridge_speed_m_s, units::kKilometrePerHour,
             "Speed limit on bridges")
        .range(5, 400);
    return s;
  }();
  return section;
}

}  // namespace trainsim::sim
