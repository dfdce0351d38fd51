// Routes given as an explicit list of blocks (route.source = "blocks"), and the list that
// rebuilds an existing route: the studio's editable form of the main track.

#include <fmt/format.h>

#include <cmath>

#include "route_builder.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/track/route_design.hpp"

namespace trainsim::track {

DesignedRoute buildBlockRoute(const std::vector<BlockSpec>& blocks, const RouteOptions& options) {
  if (blocks.empty())
    throw ConfigError("route.blocks: the list is empty; a route needs at least one block");
  const DesignRules& rules = options.rules;
  const double v = rules.design_speed_m_s;
  detail::RouteBuilder builder(options, {0.0, 0.0}, 0.0);

  // Grades start at block starts; a PVI sits wherever the grade changes.
  const double rv = std::ceil(1.2 * rules.minVerticalRadius(v) / 500.0 - 1e-9) * 500.0;
  std::vector<Pvi> pvis{{0.0, 0.0, rv}};
  double grade = blocks.front().grade;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const BlockSpec& b = blocks[i];
    auto fail = [&](const std::string& what) {
      throw ConfigError(fmt::format("route.blocks[{}]: {}", i, what));
    };
    const double start = builder.chainage();
    if (b.grade != grade) {
      pvis.push_back({start, pvis.back().z_m + grade * (start - pvis.back().chainage_m), rv});
      grade = b.grade;
    }
    if (b.type == BlockType::kSwitch)
      fail("switch blocks are reserved for main-line turnouts and cannot be laid out yet");
    if (b.type != BlockType::kCurve) {
      if (!(b.length_m > 0.0))
        fail("length_m must be positive");
      builder.straight(b.length_m, b.type);
      continue;
    }
    if (!(b.radius_m > 0.0))
      fail("a curve needs radius_m > 0");
    if (b.length_m < 0.0)
      fail("length_m (the circular arc) must not be negative");
    const double cant = b.cant_m >= 0.0 ? b.cant_m : rules.appliedCant(v, b.radius_m);
    const double transition =
        b.transition_m >= 0.0 ? b.transition_m : detail::transitionFor(rules, v, b.radius_m, cant);
    if (b.length_m <= 0.0 && transition <= 0.0)
      fail("a curve needs an arc or transitions of positive length");
    try {
      builder.curve(b.direction == Turn::kLeft ? b.radius_m : -b.radius_m, b.length_m, transition,
                    cant);
    } catch (const ConfigError& e) {
      fail(e.what());
    }
  }
  const double length = builder.chainage();
  pvis.push_back({length, pvis.back().z_m + grade * (length - pvis.back().chainage_m), 0.0});

  std::vector<std::pair<std::size_t, double>> reduced;
  VerticalProfile vertical = VerticalProfile::fromPvis(pvis, &reduced);
  DesignedRoute out = builder.finish(std::move(vertical));
  for (const auto& [index, r] : reduced) {
    const Pvi& p = pvis[index];
    out.fitting.push_back({"vertical_fit", p.chainage_m, p.chainage_m,
                           out.route.blockAt(p.chainage_m).id, r, p.radius_m, "m",
                           fmt::format("vertical curve at chainage {:.1f} m reduced from {:.0f} m "
                                       "to {:.0f} m to fit between its neighbours",
                                       p.chainage_m, p.radius_m, r)});
  }
  return out;
}

std::vector<BlockSpec> blockSpecs(const Route& route) {
  const HorizontalAlignment& h = route.track.horizontal();
  const VerticalProfile& vp = route.track.vertical();
  std::vector<BlockSpec> out;
  out.reserve(route.blocks.size());
  for (const Block& b : route.blocks) {
    BlockSpec spec;
    spec.type = b.type;
    const double len = b.chainage_end_m - b.chainage_begin_m;
    spec.grade = (vp.at(b.chainage_end_m).z_m - vp.at(b.chainage_begin_m).z_m) / len;
    if (b.type != BlockType::kCurve) {
      spec.length_m = len;
      out.push_back(spec);
      continue;
    }
    spec.radius_m = std::abs(b.radius_m);
    spec.direction = b.radius_m > 0.0 ? Turn::kLeft : Turn::kRight;
    spec.cant_m = std::abs(b.cant_m);
    spec.transition_m = 0.0;
    // A curve block is [transition] arc [transition]; read the lengths off its elements.
    const double tol = 1e-9 * std::max(1.0, b.chainage_end_m);
    for (std::size_t i = h.elementAt(b.chainage_begin_m + tol);
         i < h.elements().size() && h.elementStart(i) < b.chainage_end_m - tol; ++i) {
      const HorizontalElement& e = h.elements()[i];
      if (e.type == HorizontalElement::Type::kArc)
        spec.length_m = e.length_m;
      else if (e.type == HorizontalElement::Type::kTransition)
        spec.transition_m = e.length_m;
    }
    out.push_back(spec);
  }
  return out;
}

}  // namespace trainsim::track
