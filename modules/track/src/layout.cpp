#include "trainsim/track/layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "layout_track.hpp"
#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/random.hpp"

namespace trainsim::track {

Turnout turnoutGeometry(TurnoutType type) {
  switch (type) {
    case TurnoutType::k190_1_9:
      return {190.0, 9.0};
    case TurnoutType::k500_1_12:
      return {500.0, 12.0};
  }
  return {190.0, 9.0};
}

LayoutBlockType layoutBlockType(BlockType type) {
  switch (type) {
    case BlockType::kStraight:
      return LayoutBlockType::kStraight;
    case BlockType::kCurve:
      return LayoutBlockType::kCurve;
    case BlockType::kStation:
      return LayoutBlockType::kStation;
    case BlockType::kTunnel:
      return LayoutBlockType::kTunnel;
    case BlockType::kBridge:
      return LayoutBlockType::kBridge;
    case BlockType::kSwitch:
      return LayoutBlockType::kSwitch;
  }
  return LayoutBlockType::kStraight;
}

namespace {

using detail::collectIssues;
using detail::Interval;
using detail::PlanBox;
using detail::RunBounds;
using detail::sampleTrack;

constexpr double kSameSideGap_m = 20.0;

// The main blocks as intervals; one interval over the whole track if the route has none.
std::vector<Interval> mainIntervals(const Route& route) {
  std::vector<Interval> out;
  for (const Block& b : route.blocks)
    if (b.chainage_end_m > b.chainage_begin_m)
      out.push_back({b.chainage_begin_m, b.chainage_end_m, layoutBlockType(b.type),
                     TrackPart::kWhole, b.id, false, 0});
  if (out.empty())
    out.push_back(
        {0.0, route.track.length(), LayoutBlockType::kStraight, TrackPart::kWhole, -1, false, 0});
  return out;
}

// ---------------------------------------------------------------------------------------------
// Auxiliary-track geometry, as a lateral offset y(x) from the (straight) main track at main
// chainage x: parallel lines, straight lines at ±α and circular arcs tangent to a parallel.

struct Piece : OffsetPiece {
  LayoutBlockType type = LayoutBlockType::kStraight;
  TrackPart part = TrackPart::kWhole;
  bool in_turnout = false;
};

Piece line(double x0, double x1, double y0, double y1, LayoutBlockType type, TrackPart part,
           bool in_turnout) {
  Piece p;
  p.x0 = x0;
  p.x1 = x1;
  p.y0 = y0;
  p.y1 = y1;
  p.type = type;
  p.part = part;
  p.in_turnout = in_turnout;
  return p;
}

Piece arc(double x0, double x1, double xt, double yt, double bend, double r, LayoutBlockType type,
          TrackPart part, bool in_turnout) {
  Piece p = line(x0, x1, 0.0, 0.0, type, part, in_turnout);
  p.shape = OffsetPiece::Shape::kArc;
  p.xt = xt;
  p.yt = yt;
  p.bend = bend;
  p.r = r;
  return p;
}

// Turnout geometry in the plan of a straight main track (docs/REFERENCES.md R1.5).
struct TurnoutGeometry {
  double r = 0.0;
  double sin_a = 0.0, cos_a = 0.0, one_minus_cos_a = 0.0;
  double diagonal_m = 0.0;  // L_s
  double dead_end_m = 0.0;

  // Main-chainage length of a turnout connection and of a dead-end part.
  double turnoutLength() const { return 2.0 * r * sin_a + diagonal_m * cos_a; }
  double deadEndLength() const { return dead_end_m * cos_a + r * sin_a; }
  double endLength(bool turnout) const { return turnout ? turnoutLength() : deadEndLength(); }
};

// Pieces of an auxiliary track: neighbouring track at offset yn, parallel part at yp = yn + σd
// (σ = side: +1 left, −1 right) from chainage x0.
std::vector<Piece> auxPieces(const TurnoutGeometry& g, double x0, double yn, double yp, double side,
                             bool turnout_begin, double parallel_m, bool turnout_end) {
  std::vector<Piece> out;
  const double rs = g.r * g.sin_a;
  double x = x0;
  if (turnout_begin) {
    // Diverging arc from the neighbour, the diagonal, the reverse arc into the parallel.
    const double xa = x + rs, xb = xa + g.diagonal_m * g.cos_a, xc = xb + rs;
    const Piece a1 =
        arc(x, xa, x, yn, side, g.r, LayoutBlockType::kTurnout, TrackPart::kEntering, true);
    const Piece a2 =
        arc(xb, xc, xc, yp, -side, g.r, LayoutBlockType::kCurve, TrackPart::kEntering, true);
    out.push_back(a1);
    out.push_back(line(xa, xb, a1.offset(xa), a2.offset(xb), LayoutBlockType::kTurnout,
                       TrackPart::kEntering, true));
    out.push_back(a2);
    x = xc;
  } else {
    // Dead end outside the parallel, pointing in towards it, then the arc that turns it parallel.
    const double xa = x + g.dead_end_m * g.cos_a, xc = xa + rs;
    const Piece a =
        arc(xa, xc, xc, yp, side, g.r, LayoutBlockType::kCurve, TrackPart::kEntering, false);
    const double ya = a.offset(xa);
    out.push_back(line(x, xa, ya + side * g.dead_end_m * g.sin_a, ya, LayoutBlockType::kDeadEnd,
                       TrackPart::kEntering, false));
    out.push_back(a);
    x = xc;
  }
  out.push_back(
      line(x, x + parallel_m, yp, yp, LayoutBlockType::kParallel, TrackPart::kParallel, false));
  x += parallel_m;
  if (turnout_end) {
    const double xa = x + rs, xb = xa + g.diagonal_m * g.cos_a, xc = xb + rs;
    const Piece a2 =
        arc(x, xa, x, yp, -side, g.r, LayoutBlockType::kCurve, TrackPart::kOutgoing, true);
    const Piece a1 =
        arc(xb, xc, xc, yn, side, g.r, LayoutBlockType::kTurnout, TrackPart::kOutgoing, true);
    out.push_back(a2);
    out.push_back(line(xa, xb, a2.offset(xa), a1.offset(xb), LayoutBlockType::kTurnout,
                       TrackPart::kOutgoing, true));
    out.push_back(a1);
  } else {
    const double xa = x + rs, xb = xa + g.dead_end_m * g.cos_a;
    const Piece a =
        arc(x, xa, x, yp, side, g.r, LayoutBlockType::kCurve, TrackPart::kOutgoing, false);
    const double ya = a.offset(xa);
    out.push_back(a);
    out.push_back(line(xa, xb, ya, ya + side * g.dead_end_m * g.sin_a, LayoutBlockType::kDeadEnd,
                       TrackPart::kOutgoing, false));
  }
  // Drop zero-length pieces (a zero diagonal or dead end).
  std::erase_if(out, [](const Piece& p) { return !(p.x1 - p.x0 > 1e-12); });
  return out;
}

// Intervals of an auxiliary track: each piece cut at the main block boundaries.
std::vector<Interval> auxIntervals(const std::vector<Piece>& pieces,
                                   const std::vector<Interval>& main_blocks) {
  std::vector<Interval> out;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Piece& p = pieces[k];
    double x = p.x0;
    for (const Interval& b : main_blocks) {
      if (b.x1 <= x || b.x0 >= p.x1)
        continue;
      const double end = std::min(p.x1, b.x1);
      if (end - x > 1e-9)
        out.push_back({x, end, p.type, p.part, b.main_block_id, p.in_turnout, static_cast<int>(k)});
      x = end;
    }
    if (p.x1 - x > 1e-9)  // beyond the last block (cannot happen when blocks tile the route)
      out.push_back({x, p.x1, p.type, p.part, -1, p.in_turnout, static_cast<int>(k)});
  }
  return out;
}

// A stretch of main chainage where auxiliary tracks may be laid: a straight element alongside
// straight or station blocks only.
struct Stretch {
  double a, b;
};

std::vector<Stretch> eligibleStretches(const Route& route) {
  const HorizontalAlignment& h = route.track.horizontal();
  std::vector<Stretch> straights;
  for (std::size_t i = 0; i < h.elements().size(); ++i) {
    const HorizontalElement& e = h.elements()[i];
    if (e.type != HorizontalElement::Type::kStraight || e.curvature_start_1_m != 0.0 ||
        e.curvature_end_1_m != 0.0)
      continue;
    const double a = h.elementStart(i), b = h.elementStart(i + 1);
    if (!straights.empty() && straights.back().b == a)
      straights.back().b = b;
    else
      straights.push_back({a, b});
  }
  if (route.blocks.empty())
    return straights;
  std::vector<Stretch> out;
  for (const Stretch& st : straights) {
    double run_begin = st.a;
    bool open = true;
    for (const Block& blk : route.blocks) {
      if (blk.chainage_end_m <= st.a || blk.chainage_begin_m >= st.b)
        continue;
      const bool allowed = blk.type == BlockType::kStraight || blk.type == BlockType::kStation;
      if (allowed && !open) {
        run_begin = std::max(st.a, blk.chainage_begin_m);
        open = true;
      } else if (!allowed && open) {
        const double end = std::max(st.a, blk.chainage_begin_m);
        if (end > run_begin)
          out.push_back({run_begin, end});
        open = false;
      }
    }
    if (open && st.b > run_begin)
      out.push_back({run_begin, st.b});
  }
  return out;
}

void validate(const LayoutParams& p) {
  const auto require = [](bool ok, const char* field, double value, const char* what) {
    if (!ok)
      throw ConfigError(fmt::format("layout.{}: {} {}", field, value, what));
  };
  const double d = p.track_centre_distance_m;
  require(std::isfinite(d) && d > 0.0, "track_centre_distance_m", d, "must be positive");
  require(std::isfinite(p.polyline_spacing_m) && p.polyline_spacing_m >= 0.01, "polyline_spacing_m",
          p.polyline_spacing_m, "is below the minimum 0.01 m");
  require(p.aux_probability >= 0.0 && p.aux_probability <= 1.0, "auxiliary.probability",
          p.aux_probability, "is outside [0, 1]");
  require(p.turnout_probability >= 0.0 && p.turnout_probability <= 1.0,
          "auxiliary.turnout_probability", p.turnout_probability, "is outside [0, 1]");
  require(std::isfinite(p.aux_parallel_min_m) && p.aux_parallel_min_m > 0.0,
          "auxiliary.parallel_min_m", p.aux_parallel_min_m, "must be positive");
  require(std::isfinite(p.aux_parallel_max_m) && p.aux_parallel_max_m >= p.aux_parallel_min_m,
          "auxiliary.parallel_max_m", p.aux_parallel_max_m,
          "is below layout.auxiliary.parallel_min_m");
  require(std::isfinite(p.dead_end_length_m) && p.dead_end_length_m >= 0.0,
          "auxiliary.dead_end_length_m", p.dead_end_length_m, "must not be negative");
}

TurnoutGeometry geometryOf(const LayoutParams& p, bool turnouts_used) {
  const Turnout t = turnoutGeometry(p.turnout);
  TurnoutGeometry g;
  g.r = t.radius_m;
  // tan α = 1/n; 1 − cos α = 2 sin²(α/2) avoids cancellation.
  const double alpha = std::atan(1.0 / t.ratio);
  g.sin_a = std::sin(alpha);
  g.cos_a = std::cos(alpha);
  g.one_minus_cos_a = 2.0 * std::sin(0.5 * alpha) * std::sin(0.5 * alpha);
  g.dead_end_m = p.dead_end_length_m;
  const double d = p.track_centre_distance_m;
  const double needed = 2.0 * g.r * g.one_minus_cos_a;
  g.diagonal_m = (d - needed) / g.sin_a;
  if (turnouts_used && g.diagonal_m < 0.0)
    throw ConfigError(fmt::format(
        "layout.track_centre_distance_m ({:g} m) is too small for turnout {} (needs {:.3f} m)", d,
        nameOf(p.turnout), std::ceil(needed * 1000.0) / 1000.0));
  g.diagonal_m = std::max(0.0, g.diagonal_m);
  return g;
}

}  // namespace

Layout buildLayout(const Route& route, const LayoutParams& params, std::uint64_t seed) {
  validate(params);
  const bool aux_possible = params.aux_probability > 0.0;
  const TurnoutGeometry geo = geometryOf(params, aux_possible && params.turnout_probability > 0.0);
  const double d = params.track_centre_distance_m;
  const double spacing = params.polyline_spacing_m;
  const Track& track = route.track;

  Layout layout;
  const std::vector<Interval> blocks = mainIntervals(route);

  LayoutTrack main;
  main.id = 0;
  main.kind = TrackKind::kMain;
  main.main_chainage_end_m = track.length();
  main.offset = {OffsetPiece::line(0.0, track.length(), 0.0, 0.0)};
  RunBounds bounds(1);
  sampleTrack(track, blocks, spacing, main, &bounds.back());
  layout.tracks.push_back(std::move(main));

  int double_id = -1;
  if (params.double_track) {
    LayoutTrack dbl;
    dbl.id = double_id = 1;
    dbl.kind = TrackKind::kDouble;
    dbl.offset_m = -d;
    dbl.main_chainage_end_m = track.length();
    dbl.offset = {OffsetPiece::line(0.0, track.length(), -d, -d)};
    sampleTrack(track, blocks, spacing, dbl, &bounds.emplace_back());
    layout.tracks.push_back(std::move(dbl));
  }

  if (!aux_possible)
    return layout;

  const double p_turnout = params.turnout_probability;
  const double min_end = p_turnout <= 0.0   ? geo.deadEndLength()
                         : p_turnout >= 1.0 ? geo.turnoutLength()
                                            : std::min(geo.turnoutLength(), geo.deadEndLength());
  const double gap = std::max(kSameSideGap_m, d);
  RandomCursor rnd(RandomStream(seed, "layout.auxiliary"));
  std::array<double, 2> free_from{-std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity()};  // left, right

  for (const Stretch& st : eligibleStretches(route)) {
    throwIfCancelled();
    if (st.b - st.a < 2.0 * min_end + params.aux_parallel_min_m)
      continue;
    for (;;) {
      if (rnd.uniform() > params.aux_probability)
        break;
      const double side_draw = rnd.uniform();
      const bool turnout_begin = rnd.uniform() <= p_turnout;
      const bool turnout_end = rnd.uniform() <= p_turnout;
      const double length_draw = rnd.uniform();
      const double position_draw = rnd.uniform();
      int side = params.side == AuxSide::kLeft    ? 0
                 : params.side == AuxSide::kRight ? 1
                                                  : (side_draw <= 0.5 ? 0 : 1);
      const double ends = geo.endLength(turnout_begin) + geo.endLength(turnout_end);
      const auto available = [&](int sd) { return st.b - std::max(st.a, free_from[sd]); };
      if (available(side) < ends + params.aux_parallel_min_m) {
        if (params.side == AuxSide::kEither &&
            available(1 - side) >= ends + params.aux_parallel_min_m)
          side = 1 - side;
        else
          break;
      }
      const double lo = std::max(st.a, free_from[side]);
      const double room = st.b - lo - ends;
      const double parallel =
          std::min(room, params.aux_parallel_min_m +
                             (params.aux_parallel_max_m - params.aux_parallel_min_m) * length_draw);
      const double x0 = lo + (room - parallel) * position_draw;
      free_from[side] = x0 + ends + parallel + gap;

      // Left: beside the main track. Right: beyond the double track if there is one.
      const double sigma = side == 0 ? 1.0 : -1.0;
      const bool beyond_double = side == 1 && double_id >= 0;
      const double yn = beyond_double ? -d : 0.0;
      const double yp = yn + sigma * d;
      const std::vector<Piece> pieces =
          auxPieces(geo, x0, yn, yp, sigma, turnout_begin, parallel, turnout_end);

      LayoutTrack aux;
      aux.id = static_cast<int>(layout.tracks.size());
      aux.kind = TrackKind::kAuxiliary;
      aux.joins_track = turnout_begin || turnout_end ? (beyond_double ? double_id : 0) : -1;
      aux.offset_m = yp;
      aux.main_chainage_begin_m = pieces.front().x0;
      aux.main_chainage_end_m = pieces.back().x1;
      aux.offset.assign(pieces.begin(), pieces.end());
      std::vector<PlanBox> aux_bounds;
      sampleTrack(track, auxIntervals(pieces, blocks), spacing, aux, &aux_bounds);

      // Sound by construction beside a straight; this catches the route itself running back
      // close to the stretch.
      std::vector<ClearanceIssue> issues;
      collectIssues(track, aux, samplePolyline(track, aux), aux.id, layout.tracks, bounds, d,
                    issues);
      if (!issues.empty())
        continue;
      layout.tracks.push_back(std::move(aux));
      bounds.push_back(std::move(aux_bounds));
    }
  }
  return layout;
}

}  // namespace trainsim::track
