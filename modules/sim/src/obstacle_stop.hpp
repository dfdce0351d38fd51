#pragma once
// Private to the simulation module: where the train stops short of an obstacle in its way
// (train.stop_for_obstacles), read by the motion stage of the plan.
#include <cstddef>
#include <optional>
#include <vector>

#include "trainsim/environment/environment.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::sim::detail {

/// The first obstacle in the train's way and where the train stops short of it.
struct ObstacleStop {
  std::size_t index = 0;  ///< in objects.obstacles
  double u_m = 0.0;       ///< the front pivot's distance along the main track at the stop
};

/// The stop obstacle_margin_m short of the nearest obstacle in the train's way (the front pivot
/// at distance `u_start` at the start): one whose footprint, turned by its heading, reaches
/// within half the body's width of the main track's centre, on whichever layout track it is
/// given (those the scene leaves out, environment::obstacleLeftOut(), are passed over). Throws
/// ConfigError naming an obstacle in the way under the train where it starts, or too near ahead
/// for it to stop short of.
std::optional<ObstacleStop> obstacleStop(const track::Route& route, const track::Layout& layout,
                                         const terrain::TerrainParams& terrain,
                                         const std::vector<environment::Obstacle>& obstacles,
                                         const TrainConfig& train, double u_start);

}  // namespace trainsim::sim::detail
