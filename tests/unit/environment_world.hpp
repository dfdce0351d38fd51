// Shared by the environment tests: the default scenario's world (with small tiles), its tiles,
// and the brute-force nearest-track reference over every segment of every track.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "trainsim/environment/environment.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim {

using scenario::Json;

struct World {
  scenario::Scenario scenario;
  std::unique_ptr<sim::Plan> plan;
  std::shared_ptr<const sim::EnvironmentStage> stage;
  const environment::Environment& env() const { return *stage->environment; }
  const terrain::Railway& railway() const { return *stage->railway; }
};

// The default scenario (station, bridge, two tunnels, double and auxiliary track) with small
// tiles so the tests stay quick, and `patch` merged in.
inline World makeWorld(const Json& patch = Json::object()) {
  Json input = Json::parse(sim::defaultScenarioText());
  input["terrain"]["tile_vertices"] = 257;
  input["terrain"]["scene_tile_split"] = 2;  // scene tiles of 128 m
  input.merge_patch(patch);
  World w{sim::resolveScenario(input, "", "test"), nullptr, nullptr};
  w.plan = sim::makePlan(w.scenario);
  w.stage = sim::makeEnvironment(*w.plan, w.scenario);
  return w;
}

inline const World& defaultWorld() {
  static const World world = makeWorld();
  return world;
}

// Every segment of every track, sampled whole: the brute-force reference.
struct Segment {
  Eigen::Vector3d a, b;
  int track;
  track::LayoutBlockType type;
};
inline std::vector<Segment> allSegments(const World& w) {
  std::vector<Segment> out;
  for (const auto& t : w.railway().layout().tracks) {
    const track::Polyline line = track::samplePolyline(w.railway().main(), t);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k)
      out.push_back(
          {line.points[k], line.points[k + 1], t.id,
           w.railway().typeAt(t.id, 0.5 * (line.distance_m[k] + line.distance_m[k + 1]))});
  }
  return out;
}

// Where a point lies against `segments`, brute force, by the nearest: the distance along them to
// its foot (their plan lengths summed from the first: a track's chainage, near enough away from
// its start, for one track's segments in order), its plan distance from it signed + left, and
// its height above it.
inline std::function<std::array<double, 3>(const Eigen::Vector3d&)> nearestOn(
    std::vector<Segment> segments) {
  return [segments = std::move(segments)](const Eigen::Vector3d& p) {
    double best = std::numeric_limits<double>::infinity(), x = 0.0, lateral = 0.0, up = 0.0;
    double start = 0.0;
    for (const Segment& s : segments) {
      const Eigen::Vector2d u = (s.b - s.a).head<2>();
      const double t = std::clamp((p - s.a).head<2>().dot(u) / u.squaredNorm(), 0.0, 1.0);
      const Eigen::Vector2d off = p.head<2>() - s.a.head<2>() - t * u;
      if (off.norm() < best) {
        best = off.norm();
        x = start + t * u.norm();
        lateral = u.x() * off.y() - u.y() * off.x() >= 0.0 ? best : -best;
        up = p.z() - (s.a.z() + t * (s.b.z() - s.a.z()));
      }
      start += u.norm();
    }
    return std::array<double, 3>{x, lateral, up};
  };
}

// nearestOn() the main track: a point's main chainage, lateral offset and height above it.
inline std::function<std::array<double, 3>(const Eigen::Vector3d&)> alongTheMainTrack(
    const World& w) {
  std::vector<Segment> main;
  for (const Segment& s : allSegments(w))
    if (s.track == 0)
      main.push_back(s);
  return nearestOn(std::move(main));
}

// Indices of things by the 20 m plan cell of a point of theirs, to visit what lies near a
// point without walking everything.
class PlanGrid {
 public:
  void add(const Eigen::Vector3d& p, std::size_t i) { cells_[cellOf(p)].push_back(i); }
  // Calls f(i) for every index in the cells within `reach` cells of p's (3 × 3 for reach 1).
  template <class F>
  void near(const Eigen::Vector3d& p, long reach, F&& f) const {
    const auto [gx, gy] = cellOf(p);
    for (long dx = -reach; dx <= reach; ++dx)
      for (long dy = -reach; dy <= reach; ++dy)
        if (const auto cell = cells_.find({gx + dx, gy + dy}); cell != cells_.end())
          for (const std::size_t i : cell->second)
            f(i);
  }

 private:
  static std::pair<long, long> cellOf(const Eigen::Vector3d& p) {
    return {std::lround(std::floor(p.x() / 20.0)), std::lround(std::floor(p.y() / 20.0))};
  }
  std::map<std::pair<long, long>, std::vector<std::size_t>> cells_;
};

struct Nearest {
  double d = std::numeric_limits<double>::infinity();
  double z = 0.0;
  track::LayoutBlockType type{};
};
inline Nearest nearest(const std::vector<Segment>& segments, const Eigen::Vector2d& p,
                       bool tunnels) {
  Nearest n;
  for (const Segment& s : segments) {
    if ((s.type == track::LayoutBlockType::kTunnel) != tunnels)
      continue;
    const Eigen::Vector2d u = s.b.head<2>() - s.a.head<2>();
    const double t = std::clamp((p - s.a.head<2>()).dot(u) / u.squaredNorm(), 0.0, 1.0);
    const double d = (p - s.a.head<2>() - t * u).norm();
    if (d < n.d)
      n = {d, s.a.z() + t * (s.b.z() - s.a.z()), s.type};
  }
  return n;
}

inline Nearest nearestStation(const std::vector<Segment>& segments, const Eigen::Vector2d& p) {
  std::vector<Segment> stations;
  for (const Segment& s : segments)
    if (s.type == track::LayoutBlockType::kStation)
      stations.push_back(s);
  return nearest(stations, p, false);
}

// All tiles of the default route, made once for the geometry tests.
inline const std::vector<std::shared_ptr<const scene::Tile>>& allTiles() {
  static const auto tiles = [] {
    std::vector<std::shared_ptr<const scene::Tile>> out;
    for (const auto& i : defaultWorld().env().tiles())
      out.push_back(defaultWorld().env().tile(i));
    return out;
  }();
  return tiles;
}

}  // namespace trainsim
