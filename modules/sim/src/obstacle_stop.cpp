#include "obstacle_stop.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/error.hpp"

namespace trainsim::sim::detail {

std::optional<ObstacleStop> obstacleStop(const track::Route& route,
                                         const std::vector<environment::Obstacle>& obstacles,
                                         const TrainConfig& train, double u_start) {
  const double half_width = 0.5 * train.body.width_m;
  // From the front pivot (at u) forward to the train's front.
  const double nose = train.frontX() - 0.5 * train.vehicle.bogie_spacing_m;
  std::optional<ObstacleStop> first;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const environment::Obstacle& o = obstacles[i];
    // The main track covers the route; an obstacle off it is left out of the scene.
    if (o.track != 0 || !(o.chainage_m >= 0.0 && o.chainage_m <= route.track.length()))
      continue;
    // Its footprint in the track's axes at its chainage (x along the track, y to its left).
    const Eigen::AlignedBox2d own = environment::obstacleFootprint(o.kind);
    const Eigen::Rotation2Dd turn(o.heading_rad);
    Eigen::AlignedBox2d box;
    for (const auto corner : {Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
                              Eigen::AlignedBox2d::TopLeft, Eigen::AlignedBox2d::TopRight})
      box.extend(turn * own.corner(corner) + Eigen::Vector2d(0.0, o.offset_m));
    if (box.min().y() >= half_width || box.max().y() <= -half_width)
      continue;  // beside the train's way
    const double near_u = route.track.vertical().at(o.chainage_m).distance_m + box.min().x();
    if (near_u < u_start + nose)
      continue;  // behind the train's front at the start
    const double u = near_u - train.obstacle_margin_m - nose;
    if (u < u_start + 1.0)
      throw ConfigError(fmt::format(
          "objects.obstacles[{}]: a {} in the train's way {:.1f} m ahead of its front at the "
          "start, too near for it to stop train.obstacle_margin_m ({:g} m) short of it: move "
          "it, lower the margin, or set train.stop_for_obstacles false to run through it",
          i, nameOf(o.kind), near_u - u_start - nose, train.obstacle_margin_m));
    if (!first || u < first->u_m)
      first = ObstacleStop{i, u};
  }
  return first;
}

}  // namespace trainsim::sim::detail
