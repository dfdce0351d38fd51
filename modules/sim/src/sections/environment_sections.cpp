// The `terrain`, `assets` and `objects` sections: declarations bound to the environment's
// parameter structs (terrain::TerrainParams, environment::AssetParams, ObjectParams).

#include <fmt/format.h>

#include <cmath>

#include "trainsim/sim/config.hpp"

namespace trainsim::sim {
namespace {

using scenario::Binding;
using scenario::Problem;
namespace units = scenario::units;
constexpr scenario::Unit kM = units::si("m");

const Binding<environment::ObjectKindParams>& objectKindBinding() {
  static const Binding<environment::ObjectKindParams> binding = [] {
    using K = environment::ObjectKindParams;
    Binding<K> b;
    b.number("density_per_ha", &K::density_per_ha, units::si("1/ha"),
             "Candidates per hectare (some are dropped to keep footprints apart)")
        .range(0, 150);
    b.number("min_track_distance_m", &K::min_track_distance_m, kM,
             "Least distance from any track centre to the footprint's edge")
        .range(4.5, 1000);
    return b;
  }();
  return binding;
}

}  // namespace

const scenario::Section<terrain::TerrainParams>& terrainSection() {
  static const scenario::Section<terrain::TerrainParams> section = [] {
    using T = terrain::TerrainParams;
    scenario::Section<T> s{"terrain",
                           "Landscape height map along the tracks (made only for a LiDAR, a camera "
                           "or plan --scene).",
                           {},
                           {}};
    Binding<T>& b = s.binding;
    b.number("spacing_m", &T::spacing_m, kM, "Height-map vertex spacing").range(0.25, 10);
    b.integer("tile_vertices", &T::tile_vertices, "", "Vertices per side of a tile")
        .range(17, 2049);  // 4.2 M heights: about 0.3 GB while a tile is made
    b.number("tile_margin_m", &T::tile_margin_m, kM, "Tiles within this of a track exist")
        .range(50, 5000);
    b.number("d_near_m", &T::d_near_m, kM, "Ground at the track's formation within this")
        .range(1.5, 50);
    b.number("d_near_station_m", &T::d_near_station_m, kM,
             "The same in stations (a station's track counts as d_near_station_m - d_near_m "
             "nearer, so the ground leaves the formation smoothly past its ends)")
        .range(1.5, 100);
    b.number("d_far_m", &T::d_far_m, kM,
             "Noise height beyond this (linear blend in between; from a station's track, that "
             "much further)")
        .range(2, 200);
    b.number("formation_depth_m", &T::formation_depth_m, kM,
             "Top of rail down to the ground under the ballast")
        .range(0.5, 3);
    b.integer("octaves", &T::octaves, "", "Noise octaves").range(1, 12);
    b.number("amplitude_m", &T::amplitude_m, kM, "Noise amplitude").range(0, 500);
    b.number("wavelength_m", &T::wavelength_m, kM, "Wavelength of the first octave").range(10, 1e5);
    b.number("persistence", &T::persistence, units::kNone, "Amplitude ratio between octaves")
        .range(0.05, 0.95);
    b.number("regional_radius_m", &T::regional_radius_m, kM,
             "Reach of the tracks' level under the noise")
        .range(100, 1e4);
    b.number("valley_depth_m", &T::valley_depth_m, kM, "Valley under a bridge, below the formation")
        .range(0, 200);
    b.number("valley_width_m", &T::valley_width_m, kM, "Half-width of a valley at full depth")
        .range(10, 2000);
    b.number("tunnel_crown_m", &T::tunnel_crown_m, kM, "Tunnel crown above the top of rail")
        .range(5, 20);
    b.number("tunnel_cover_m", &T::tunnel_cover_m, kM, "Ground above the tunnel crown")
        .range(1, 200);
    b.number("tunnel_half_width_m", &T::tunnel_half_width_m, kM, "Half-width of the tunnel tube")
        .range(3, 30);
    b.number("cut_slope", &T::cut_slope, units::kNone, "Rise per metre of cuttings at portals")
        .range(0.2, 5);
    b.number("hill_slope", &T::hill_slope, units::kNone,
             "Fall per metre of the ground beside a tunnel")
        .range(0.1, 5);
    b.number("simplify_tolerance_m", &T::simplify_tolerance_m, kM,
             "Terrain meshes within this vertical error of the grid (0: the full grid)")
        .range(0, 5);
    b.integer("scene_tile_split", &T::scene_tile_split, "",
              "The scene streams in tiles this many times finer than the terrain tiles (per side)")
        .range(1, 16);
    b.check([](const T& t, const scenario::FieldPaths<T>& at, std::vector<Problem>& out) {
      if ((t.tile_vertices - 1) % t.scene_tile_split != 0)
        out.push_back({at(t.scene_tile_split), "must divide " + at.key(t.tile_vertices) + " - 1"});
    });
    b.notAbove(&T::d_near_m, &T::d_far_m);
    b.notAbove(&T::d_near_station_m, &T::d_far_m);
    return s;
  }();
  return section;
}

const scenario::Section<environment::AssetParams>& assetsSection() {
  static const scenario::Section<environment::AssetParams> section = [] {
    using A = environment::AssetParams;
    scenario::Section<A> s{
        "assets", "Track assets: rails, sleepers, ballast, catenary, platforms, fences.", {}, {}};
    Binding<A>& b = s.binding;
    b.number("gauge_mm", &A::gauge_m, units::kMillimetre, "Track gauge between running faces")
        .range(1000, 1700);
    b.number("rail_inclination", &A::rail_inclination, units::kNone,
             "Rail cant toward the track (1/40)")
        .range(0, 0.1);
    b.number("sleeper_spacing_m", &A::sleeper_spacing_m, kM, "Sleeper spacing").range(0.4, 1.5);
    b.number("sleeper_length_m", &A::sleeper_length_m, kM, "Sleeper length").range(1.8, 3.5);
    b.number("sleeper_width_m", &A::sleeper_width_m, kM, "Sleeper width").range(0.1, 0.5);
    b.number("sleeper_height_m", &A::sleeper_height_m, kM, "Sleeper height").range(0.1, 0.4);
    b.number("ballast_shoulder_m", &A::ballast_shoulder_m, kM, "Ballast beyond the sleeper ends")
        .range(0, 1.5);
    b.number("ballast_slope", &A::ballast_slope, units::kNone,
             "Ballast slope, horizontal per vertical")
        .range(0.5, 4);
    b.boolean(
        "catenary", &A::catenary,
        "Masts and wires along the main and double track, and wires over the auxiliary tracks' "
        "parallel parts (hung from the same masts)");
    b.number("mast_span_m", &A::mast_span_m, kM, "Longest span between masts").range(10, 100);
    b.number("mast_offset_m", &A::mast_offset_m, kM, "Mast from the outermost track centre")
        .range(2.5, 10);
    b.number("mast_height_m", &A::mast_height_m, kM, "Mast height above the rails").range(6, 15);
    b.number("contact_height_m", &A::contact_height_m, kM, "Contact wire above the top of rail")
        .range(4.5, 6.5);
    b.number("system_height_m", &A::system_height_m, kM,
             "Messenger above the contact wire at supports")
        .range(0.7, 2.5);
    b.number("stagger_m", &A::stagger_m, kM, "Contact wire stagger").range(0, 0.4);
    b.number("dropper_spacing_m", &A::dropper_spacing_m, kM, "Largest dropper spacing")
        .range(2, 20);
    b.number("platform_height_m", &A::platform_height_m, kM, "Platform above the top of rail")
        .range(0.2, 1.3);
    b.number("platform_edge_m", &A::platform_edge_m, kM, "Platform edge from the track centre")
        .range(1.5, 2.5);
    b.number("platform_width_m", &A::platform_width_m, kM, "Platform width").range(1, 30);
    b.number("bridge_pier_spacing_m", &A::bridge_pier_spacing_m, kM, "Pier spacing").range(10, 200);
    b.number("fence_probability", &A::fence_probability, units::kNone, "Fence per block and side")
        .range(0, 1);
    b.number("fence_offset_m", &A::fence_offset_m, kM, "Fence from the outermost track centre")
        .range(3.5, 50);
    b.number("signal_offset_m", &A::signal_offset_m, kM,
             "Signal post from the outermost track centre")
        .range(2.2, 10);
    b.number("signal_caution", &A::signal_caution, units::kNone,
             "Share of signals showing caution (yellow lamp lit); the rest of the train's own "
             "track show proceed (green)")
        .range(0, 1);
    b.number("signal_stop", &A::signal_stop, units::kNone,
             "Share of signals of other tracks showing stop (red lamp lit); the train's own "
             "track never shows stop")
        .range(0, 1);
    b.check([](const A& a, const auto& at, std::vector<Problem>& out) {
      if (a.signal_caution + a.signal_stop > 1.0)
        out.push_back({at(a.signal_stop),
                       fmt::format("{:g} plus {} {:g} is more than 1: they must leave a share for "
                                   "proceed",
                                   a.signal_stop, at(a.signal_caution), a.signal_caution)});
      if (a.mast_offset_m >= a.fence_offset_m)
        out.push_back(
            {at(a.fence_offset_m), "must lie beyond the masts (" + at(a.mast_offset_m) + ")"});
    });
    return s;
  }();
  return section;
}

const Binding<environment::Obstacle>& obstacleBinding() {
  static const Binding<environment::Obstacle> binding = [] {
    using Ob = environment::Obstacle;
    Binding<Ob> b;
    b.choice("kind", &Ob::kind,
             "What stands there: a person (1.75 m), a car (4.4 m, at a level crossing) or a cow; "
             "classes person, car and animal");
    b.integer("track", &Ob::track, "",
              "Layout track it stands on or beside (railroad.json's id; 0 the main track)")
        .range(0, 1000);
    b.number("chainage_m", &Ob::chainage_m, kM, "Main chainage (on the track's stretch)")
        .range(0, 1e7);
    b.number("offset_m", &Ob::offset_m, kM,
             "From the track's centre, + left: it stands on the highest surface there (a track's "
             "sleepers, its ballast bed's top or shoulder, a station's platform, a bridge's deck "
             "or parapet, the terrain; in a tunnel the formation)")
        .range(-50, 50);
    b.number("heading_deg", &Ob::heading_rad, units::kDegree,
             "Which way it faces, counter-clockwise from the track's direction (90: across it, "
             "to the left)")
        .range(-360, 360);
    return b;
  }();
  return binding;
}

const scenario::Section<environment::ObjectParams>& objectsSection() {
  static const scenario::Section<environment::ObjectParams> section = [] {
    using O = environment::ObjectParams;
    scenario::Section<O> s{
        "objects", "Trackside objects: one entry per kind of the registry.", {}, {}};
    Binding<O>& b = s.binding;
    b.number("cell_m", &O::cell_m, kM, "Candidate lattice spacing (at most one candidate per cell)")
        .range(2, 50);
    const auto kinds = environment::objectKinds();
    for (std::size_t k = 0; k < kinds.size(); ++k)
      b.object(
          std::string(kinds[k].name),
          [k](O& o) -> environment::ObjectKindParams& { return o.kinds[k]; }, objectKindBinding(),
          std::string(kinds[k].description));
    b.array("obstacles", &O::obstacles, obstacleBinding(), "One obstacle.",
            "Obstacles placed by hand on or beside the tracks, the positives of obstacle "
            "detection: each an object of its own (instances.csv gives its track). One on a "
            "track the layout does not have, off its track's stretch, or in a tunnel reaching "
            "beyond its bore's walls into the rock, is left out with a warning (validate and "
            "every run say which and why): a layout is drawn per seed, and one list should "
            "serve every seed's")
        .maxItems(10000);
    // A cell holds one candidate at most: densities asking for more than one a cell would be
    // cut short, the later kinds of the registry most (they draw from what the first leave).
    b.check([](const O& o, const auto& at, std::vector<Problem>& out) {
      double per_ha = 0.0;
      for (const environment::ObjectKindParams& k : o.kinds)
        per_ha += k.density_per_ha;
      if (const double per_cell = per_ha * o.cell_m * o.cell_m / 1e4; per_cell > 1.0)
        out.push_back({at(o.cell_m),
                       fmt::format("{:g} m cells hold {:.2f} candidates each at the kinds' "
                                   "density_per_ha (together {:g} per ha), but a cell holds one "
                                   "at most: use cells of {:.1f} m or less, or lower the densities",
                                   o.cell_m, per_cell, per_ha,
                                   std::floor(std::sqrt(1e4 / per_ha) * 10.0) / 10.0)});
    });
    return s;
  }();
  return section;
}

}  // namespace trainsim::sim
