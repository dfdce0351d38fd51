#pragma once

#include <vector>

#include <Eigen/Core>

#include "trainsim/track/layout.hpp"

namespace trainsim::track::detail {

/// A stretch of one layout track between two main chainages, with the block it belongs to.
struct Interval {
  double x0 = 0.0, x1 = 0.0;  // main chainage
  LayoutBlockType type = LayoutBlockType::kStraight;
  TrackPart part = TrackPart::kWhole;
  int main_block_id = -1;
  bool in_turnout = false;
  int piece = 0;  // the offset piece that gives the offset
};

/// Plan-view (world x, y) bounds.
struct PlanBox {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  void add(const Eigen::Vector3d& p);
  void inflate(double margin_m);
  bool meets(const PlanBox& o) const;
};

/// Plan bounds of every run of every track (indexed like the tracks), made while a layout is
/// built or checked and dropped after: the plan keeps only the runs.
using RunBounds = std::vector<std::vector<PlanBox>>;

/// Fills the track's runs, blocks and turnout ranges from consecutive intervals (its offset
/// law already set), and the runs' bounds if asked. Consecutive intervals with the same labels
/// form one block; intervals are cut so that no run spans more than kPolylineRunLength_m.
void sampleTrack(const Track& main, const std::vector<Interval>& intervals, double spacing_m,
                 LayoutTrack& track, std::vector<PlanBox>* bounds = nullptr);

/// Appends the issues of `track` (polyline `own`, index `self`, not necessarily in `tracks`
/// yet) against every other track of `tracks` whose runs come within min_distance_m of it.
void collectIssues(const Track& main, const LayoutTrack& track, const Polyline& own, int self,
                   const std::vector<LayoutTrack>& tracks, const RunBounds& bounds,
                   double min_distance_m, std::vector<ClearanceIssue>& out);

}  // namespace trainsim::track::detail
