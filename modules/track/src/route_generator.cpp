#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "route_builder.hpp"
#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/track/route_design.hpp"

namespace trainsim::track {
namespace {

double roundUp(double x, double step) {
  return std::ceil(x / step - 1e-9) * step;
}

void checkParams(const RouteGeneratorParams& p, const DesignRules& rules) {
  auto fail = [](const std::string& m) { throw ConfigError("route.generator: " + m); };
  if (p.arc_length_min_m > p.arc_length_max_m)
    fail("arc_length_min_m is larger than arc_length_max_m");
  if (p.grade_length_min_m > p.grade_length_max_m)
    fail("grade_length_min_m is larger than grade_length_max_m");
  if (p.grade_max > rules.max_grade + 1e-12)
    fail(fmt::format("grade_max_permille ({:.3g}) exceeds design.max_grade_permille ({:.3g})",
                     p.grade_max * 1e3, rules.max_grade * 1e3));
  if (p.station.probability + p.tunnel.probability + p.bridge.probability > 1.0 + 1e-12)
    fail("the station, tunnel and bridge probabilities add up to more than 1");
  for (const auto* s : {&p.station, &p.tunnel, &p.bridge}) {
    if (s->length_min_m > s->length_max_m)
      fail("a special block has length_min_m larger than length_max_m");
  }
  if (p.radius_min_m > p.radius_max_m)
    fail(fmt::format("radius_min_m ({:g} m) is larger than radius_max_m ({:g} m)", p.radius_min_m,
                     p.radius_max_m));
  const double design_min = rules.minRadius(rules.design_speed_m_s);
  if (design_min > p.radius_max_m)
    fail(fmt::format(
        "radius_max_m ({:g} m) is below the smallest radius design.design_speed_km_h allows "
        "({:.0f} m): raise it or lower the design speed",
        p.radius_max_m, design_min));
}

}  // namespace

DesignedRoute generateRoute(const RouteGeneratorParams& params, const RouteOptions& options,
                            std::uint64_t seed) {
  const DesignRules& rules = options.rules;
  checkParams(params, rules);
  RandomCursor rnd(RandomStream(seed, "route.generator"));
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rnd.uniform(); };

  const double v = rules.design_speed_m_s;
  const double r_min = std::max(params.radius_min_m, rules.minRadius(v));
  const double r_max = std::max(r_min, params.radius_max_m);
  const double min_len = rules.minElementLength(v);
  const double arc_lo = std::max(min_len, params.arc_length_min_m);
  const double arc_hi = std::max(arc_lo, params.arc_length_max_m);

  // Mean straight length that gives the requested share of curves.
  const double r_mid = 0.5 * (r_min + r_max);
  const double typical_curve =
      0.5 * (arc_lo + arc_hi) +
      2.0 * detail::transitionFor(rules, v, r_mid, rules.appliedCant(v, r_mid));
  const double share = std::clamp(params.curve_share, 0.0, 0.95);
  const double mean_straight =
      share <= 0.0 ? params.length_m : typical_curve * (1.0 - share) / share;

  detail::RouteBuilder builder(options, {0.0, 0.0}, 0.0);
  double heading = 0.0;  // net turn so far; curves lean back towards the start direction
  const double margin = std::max(50.0, 0.5 * min_len);
  while (builder.chainage() < params.length_m) {
    throwIfCancelled();
    // A straight, possibly holding one station, tunnel or bridge.
    double straight = std::max(min_len, mean_straight * uniform(0.5, 1.5));
    const double pick = rnd.uniform();
    const double len_draw = rnd.uniform();
    struct Special {
      BlockType type;
      const SpecialBlockParams* p;
    };
    const Special specials[] = {{BlockType::kStation, &params.station},
                                {BlockType::kTunnel, &params.tunnel},
                                {BlockType::kBridge, &params.bridge}};
    double acc = 0.0;
    const Special* chosen = nullptr;
    for (const Special& sp : specials) {
      acc += sp.p->probability;
      if (pick <= acc) {
        chosen = &sp;
        break;
      }
    }
    const double remaining = params.length_m - builder.chainage();
    if (chosen) {
      const double len =
          chosen->p->length_min_m + (chosen->p->length_max_m - chosen->p->length_min_m) * len_draw;
      if (len + 2.0 * margin <= remaining) {
        straight = std::min(std::max(straight, len + 2.0 * margin), remaining);
        const double before = 0.5 * (straight - len);
        builder.straight(before);
        builder.straight(len, chosen->type);
        builder.straight(straight - before - len);
      } else {
        chosen = nullptr;
      }
    }
    if (!chosen)
      builder.straight(std::min(straight, remaining));
    if (builder.chainage() >= params.length_m || share <= 0.0)
      break;

    // A curve: radius, direction (leaning back towards the initial heading), cant, transitions.
    const double radius = uniform(r_min, r_max);
    const double toward = heading > 0.0 ? -1.0 : 1.0;
    const double direction = rnd.uniform() < 0.7 ? toward : -toward;
    const double cant = rules.appliedCant(v, radius);
    const double transition = detail::transitionFor(rules, v, radius, cant);
    const double arc = uniform(arc_lo, arc_hi);
    // Leave room for the closing straight.
    if (builder.chainage() + 2.0 * transition + arc + min_len > params.length_m) {
      builder.straight(params.length_m - builder.chainage());
      break;
    }
    builder.curve(direction * radius, arc, transition, cant);
    heading += direction * (arc + transition) / radius;
  }
  const double length = builder.chainage();

  // Vertical profile: grades between randomly spaced PVIs, joined by curves of radius R_v.
  // PVIs are far enough apart that neighbouring vertical curves never overlap.
  const double rv = roundUp(1.2 * rules.minVerticalRadius(v), 500.0);
  const double grade_max = std::min(params.grade_max, rules.max_grade);
  const double tangent_max = rv * std::tan(std::atan(grade_max));  // T for |Δθ| = 2 grade_max
  const double spacing_min = std::max(params.grade_length_min_m, 2.0 * tangent_max + 50.0);
  const double spacing_max = std::max(spacing_min, params.grade_length_max_m);

  // Draw PVI chainages on the builder's blocks (stations need flat-enough grades).
  DesignedRoute flat = builder.finish(VerticalProfile(length + 1.0, 0.0));
  std::vector<Pvi> pvis{{0.0, 0.0, rv}};
  while (pvis.back().chainage_m < length) {
    const double next =
        std::min(pvis.back().chainage_m + uniform(spacing_min, spacing_max), length + spacing_min);
    double grade = uniform(-grade_max, grade_max);
    const double a = pvis.back().chainage_m - tangent_max - margin;
    const double b = next + tangent_max + margin;
    for (const Block& blk : flat.route.blocks) {
      if (blk.type == BlockType::kStation && blk.chainage_end_m > a && blk.chainage_begin_m < b)
        grade = std::clamp(grade, -0.9 * rules.station_max_grade, 0.9 * rules.station_max_grade);
    }
    pvis.push_back({next, pvis.back().z_m + grade * (next - pvis.back().chainage_m), rv});
  }
  std::vector<std::pair<std::size_t, double>> reduced;
  VerticalProfile vertical = VerticalProfile::fromPvis(pvis, &reduced);
  if (!reduced.empty())
    throw RuntimeError("route generator: vertical curves overlap (generator bug)");

  DesignedRoute out{Route{Track(flat.route.track.horizontal(), std::move(vertical),
                                flat.route.track.cant(), options.cant_rotation),
                          flat.route.blocks},
                    flat.stops,
                    {}};
  return out;
}

}  // namespace trainsim::track
