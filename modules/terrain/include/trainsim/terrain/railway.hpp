#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "trainsim/track/layout.hpp"

namespace trainsim::terrain {

/// A stretch of one layout track by main chainage (merged polyline runs).
struct Stretch {
  int track = 0;
  double x0 = 0.0, x1 = 0.0;
};

/// A main-track structure the terrain and the assets shape themselves around: a bridge, a
/// tunnel or a station, with its chainage range on the main track and where the main track is
/// at either end (plan view, shifted): worked out once, so that a tile can tell whether the
/// structure is near without asking the track.
struct Structure {
  track::BlockType type = track::BlockType::kStraight;
  int block_id = 0;
  double chainage_begin_m = 0.0, chainage_end_m = 0.0;
  Eigen::Vector2d begin_xy = Eigen::Vector2d::Zero(), end_xy = Eigen::Vector2d::Zero();
};

/// What the environment needs to know of the railway, with a coarse spatial index: the plan
/// box of every polyline run of every layout track (O(route / 500 m) numbers), so that a tile
/// asks only for the stretches near it and samples only those (never a scan of all segments).
/// Everything it returns is moved by `shift` (tests use it to put the same railway 1000 km
/// from the scenario origin). Holds references to `route` and `layout`, which must outlive it.
class Railway {
 public:
  Railway(const track::Route& route, const track::Layout& layout,
          const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

  /// The stretches of every track whose runs come within `margin` (plan) of the box [lo, hi],
  /// in track order, merged where consecutive.
  std::vector<Stretch> stretchesNear(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                     double margin) const;
  /// The polyline points of a stretch (samplePolyline: the same bits whichever window asks).
  track::Polyline polyline(const Stretch& stretch) const;
  /// The frame of a track at main chainage x (trackFrame, shifted).
  track::TrackFrame frame(int track, double main_chainage_m) const;
  /// The layout block type of a track at a distance along its polyline.
  track::LayoutBlockType typeAt(int track, double distance_m) const;

  const track::Route& route() const { return route_; }
  const track::Track& main() const { return route_.track; }
  const track::Layout& layout() const { return layout_; }
  /// How far everything the railway returns is moved from where the plan put it.
  const Eigen::Vector3d& shift() const { return shift_; }
  /// Bridges, tunnels and stations of the main track, in chainage order.
  const std::vector<Structure>& structures() const { return structures_; }
  /// Every run's plan box (for deciding which tiles exist).
  struct RunBox {
    int track = 0;
    double x0 = 0.0, x1 = 0.0;
    Eigen::Vector2d lo, hi;
  };
  const std::vector<RunBox>& runBoxes() const { return boxes_; }

 private:
  const track::Route& route_;
  const track::Track& main_;
  const track::Layout& layout_;
  Eigen::Vector3d shift_;
  std::vector<RunBox> boxes_;
  std::vector<Structure> structures_;
};

/// Plan distance to the nearest track centreline over a box: the segments of every track near
/// the box in a uniform grid of `cell_m` cells, so a query looks at a few cells, not at every
/// segment.
class TrackDistance {
 public:
  TrackDistance(const Railway& railway, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                double reach, double cell_m = 16.0);
  /// The distance from (x, y) to the nearest track segment, or infinity beyond `reach`.
  double operator()(double x, double y) const;

 private:
  struct Segment {
    Eigen::Vector2d a, b;
  };
  Eigen::Vector2d lo_;
  double reach_, cell_;
  int nx_ = 0, ny_ = 0;
  std::vector<Segment> segments_;
  std::vector<std::vector<std::uint32_t>> cells_;
};

}  // namespace trainsim::terrain
