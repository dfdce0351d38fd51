#include "route_builder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/core/error.hpp"

namespace trainsim::track::detail {

RouteBuilder::RouteBuilder(const RouteOptions& options, Eigen::Vector2d start, double heading_rad)
    : options_(options), start_(std::move(start)), heading_(heading_rad) {}

void RouteBuilder::addBlock(BlockType type, double length_m, double radius_m, double cant_m) {
  const double begin = blocks_.empty() ? 0.0 : blocks_.back().chainage_end_m;
  if (!blocks_.empty() && type == BlockType::kStraight &&
      blocks_.back().type == BlockType::kStraight) {
    blocks_.back().chainage_end_m += length_m;
    return;
  }
  Block b;
  b.id = static_cast<int>(blocks_.size());
  b.type = type;
  b.chainage_begin_m = begin;
  b.chainage_end_m = begin + length_m;
  b.radius_m = radius_m;
  b.cant_m = cant_m;
  blocks_.push_back(b);
}

void RouteBuilder::straight(double length_m, BlockType type) {
  if (length_m <= 0.0)
    return;
  pending_ += length_m;
  addBlock(type, length_m, 0.0, 0.0);
}

void RouteBuilder::flush() {
  if (pending_ <= 0.0)
    return;
  elements_.push_back(HorizontalElement::straight(pending_));
  cant_.push_back({pending_, 0.0, 0.0, RampShape::kLinear});
  s_ += pending_;
  pending_ = 0.0;
}

void RouteBuilder::curve(double signed_radius_m, double arc_length_m, double transition_m,
                         double cant_m) {
  flush();
  // A transition turns the track by L/2R (clothoid and Bloss alike). Past a right angle it is
  // no railway but a spiral winding on itself (a 10 m radius with the transition a 200 km/h
  // design asks for turns it some 750 times): refuse it rather than plan it.
  const double turn = transition_m / (2.0 * std::abs(signed_radius_m));
  if (turn > std::numbers::pi / 2.0) {
    const double begin = blocks_.empty() ? 0.0 : blocks_.back().chainage_end_m;
    throw ConfigError(fmt::format(
        "curve at chainage {:.0f} m: its {:.0f} m transitions to a {:g} m radius turn the track by "
        "{:.0f} degrees each (at most 90): use a larger radius, a shorter transition or a lower "
        "design speed",
        begin, transition_m, std::abs(signed_radius_m), turn * 180.0 / std::numbers::pi));
  }
  const double k = 1.0 / signed_radius_m;
  // Bank into the curve: a left-hand curve (k > 0) raises the right rail (negative cant).
  const double d = k > 0.0 ? -std::abs(cant_m) : std::abs(cant_m);
  const RampShape ramp =
      options_.transition_shape == TransitionShape::kBloss ? RampShape::kBloss : RampShape::kLinear;
  double length = 0.0;
  if (transition_m > 0.0) {
    elements_.push_back(
        HorizontalElement::transition(transition_m, 0.0, k, options_.transition_shape));
    cant_.push_back({transition_m, 0.0, d, ramp});
    length += transition_m;
  }
  if (arc_length_m > 0.0) {
    elements_.push_back(HorizontalElement::arc(arc_length_m, signed_radius_m));
    cant_.push_back({arc_length_m, d, d, RampShape::kLinear});
    length += arc_length_m;
  }
  if (transition_m > 0.0) {
    elements_.push_back(
        HorizontalElement::transition(transition_m, k, 0.0, options_.transition_shape));
    cant_.push_back({transition_m, d, 0.0, ramp});
    length += transition_m;
  }
  s_ += length;
  addBlock(BlockType::kCurve, length, signed_radius_m, d);
}

DesignedRoute RouteBuilder::finish(VerticalProfile vertical) {
  flush();
  const DesignRules& rules = options_.rules;
  DesignedRoute out{Route{Track(HorizontalAlignment(start_, heading_, elements_),
                                std::move(vertical), CantProfile(cant_), options_.cant_rotation),
                          blocks_},
                    {},
                    {}};
  for (Block& b : out.route.blocks) {
    b.speed_limit_m_s = rules.blockSpeed(b.type);
    if (b.type == BlockType::kCurve)
      b.speed_limit_m_s = std::min(b.speed_limit_m_s, rules.curveSpeed(b.radius_m, b.cant_m));
    if (b.type == BlockType::kStation && options_.station_stops) {
      b.stop = true;
      // The front of the train stops 20 m before the end of the platform (or mid-platform).
      const double len = b.chainage_end_m - b.chainage_begin_m;
      out.stops.emplace_back(b.chainage_end_m - std::min(20.0, 0.5 * len),
                             options_.station_dwell_s);
    }
  }
  return out;
}

double transitionFor(const DesignRules& rules, double v, double radius_m, double cant_m) {
  const double deficiency = rules.equilibriumCant(v, radius_m) - cant_m;
  const double length = std::max(20.0, rules.minTransitionLength(v, cant_m, deficiency));
  return std::ceil(length / 5.0 - 1e-9) * 5.0;
}

Eigen::Vector2d transitionEnd(double length_m, double radius_m, TransitionShape shape) {
  const HorizontalAlignment t(
      {0.0, 0.0}, 0.0, {HorizontalElement::transition(length_m, 0.0, 1.0 / radius_m, shape)});
  return t.at(length_m).position_m;
}

}  // namespace trainsim::track::detail
