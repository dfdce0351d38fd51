#pragma once

#include <vector>

#include "trainsim/track/route_design.hpp"

namespace trainsim::track::detail {

/// Lays a main track out element by element and keeps its blocks and cant in step. Shared by
/// the random generator and the waypoint import so that both give the same route model.
class RouteBuilder {
 public:
  RouteBuilder(const RouteOptions& options, Eigen::Vector2d start, double heading_rad);

  /// A straight of `length` whose block has `type`; consecutive straights form one element.
  void straight(double length_m, BlockType type = BlockType::kStraight);
  /// Transition, arc of `signed_radius` (positive left), transition: one curve block. The cant
  /// magnitude is banked into the curve and ramped along the transitions.
  void curve(double signed_radius_m, double arc_length_m, double transition_m, double cant_m);

  double chainage() const { return s_ + pending_; }

  /// The route over the laid-out chainage with the given vertical profile.
  DesignedRoute finish(VerticalProfile vertical);

 private:
  void flush();
  void addBlock(BlockType type, double length_m, double radius_m, double cant_m);

  RouteOptions options_;
  Eigen::Vector2d start_;
  double heading_;
  std::vector<HorizontalElement> elements_;
  std::vector<CantElement> cant_;
  std::vector<Block> blocks_;
  double s_ = 0.0;        // chainage of the flushed elements
  double pending_ = 0.0;  // straight not yet emitted
};

/// Transition length for a curve of radius R and cant D at speed v: the design-rule minimum,
/// at least 20 m, rounded up to 5 m.
double transitionFor(const DesignRules& rules, double v, double radius_m, double cant_m);

/// Local end point (x along the start tangent, y to the left) of a transition from straight to
/// curvature 1/R over length L.
Eigen::Vector2d transitionEnd(double length_m, double radius_m, TransitionShape shape);

}  // namespace trainsim::track::detail
