#include "obstacle_stop.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/error.hpp"

namespace trainsim::sim::detail {

std::optional<ObstacleStop> obstacleStop(const track::Route& route, const track::Layout& layout,
                                         const terrain::TerrainParams& terrain,
                                         const std::vector<environment::Obstacle>& obstacles,
                                         const TrainConfig& train, double u_start) {
  const double half_width = 0.5 * train.body.width_m;
  // From the front pivot (at u) forward to the train's front.
  const double nose = train.frontX() - 0.5 * train.vehicle.bogie_spacing_m;
  const auto plan = [](const Eigen::Vector3d& v) {
    return Eigen::Vector2d(v.head<2>()).normalized();
  };
  std::optional<ObstacleStop> first;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    if (environment::obstacleLeftOut(layout, route.blocks, terrain, obstacles[i]))
      continue;  // left out of the scene
    environment::Obstacle o = obstacles[i];
    const track::LayoutTrack& on = layout.tracks[static_cast<std::size_t>(o.track)];
    o.chainage_m = std::clamp(o.chainage_m, on.main_chainage_begin_m, on.main_chainage_end_m);
    // Its footprint's corners in plan, on whichever track it is given, then in the main track's
    // axes at its chainage (x along the main track, y to its left): one given on the double
    // track may stand across the main track.
    const track::TrackFrame own = track::trackFrame(
        route.track, layout.tracks[static_cast<std::size_t>(o.track)], o.chainage_m);
    const track::TrackFrame main = track::trackFrame(route.track, layout.tracks[0], o.chainage_m);
    const Eigen::Vector2d t = plan(own.tangent), l(-t.y(), t.x());
    const Eigen::Vector2d centre = (own.position + o.offset_m * own.left).head<2>();
    const Eigen::Vector2d t0 = plan(main.tangent), l0(-t0.y(), t0.x());
    Eigen::AlignedBox2d box;
    for (const Eigen::Vector2d& c : environment::obstacleCorners(o)) {
      const Eigen::Vector2d d = centre + c.x() * t + c.y() * l - main.position.head<2>();
      box.extend(Eigen::Vector2d(d.dot(t0), d.dot(l0)));
    }
    if (box.min().y() >= half_width || box.max().y() <= -half_width)
      continue;  // beside the train's way
    const double near_u = route.track.vertical().at(o.chainage_m).distance_m + box.min().x();
    const double u = near_u - train.obstacle_margin_m - nose;
    if (near_u < u_start + nose)
      throw ConfigError(fmt::format(
          "objects.obstacles[{}]: a {} under the train where it starts (its front at {:.1f} m of "
          "the route): move it ahead of the train, or set train.stop_for_obstacles false to "
          "leave it where it is",
          i, nameOf(o.kind), u_start + nose));
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
