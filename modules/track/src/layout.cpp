#include "trainsim/track/layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include <Eigen/Geometry>

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

constexpr double kSameSideGap_m = 20.0;
constexpr double kClearanceTolerance_m = 1e-6;

// ---------------------------------------------------------------------------------------------
// Polylines: a track's points are P(x) = main(x) + y(x) l(x) at the main chainages of its runs,
// made on demand run by run.

// The point of `track` at main chainage x on offset piece `piece`. The main track (y = 0) is
// the main centreline itself, bit for bit.
Eigen::Vector3d pointOf(const Track& main, const LayoutTrack& track, int piece, double x) {
  const TrackPoint tp = main.atChainage(x);
  const double y = track.offset[static_cast<std::size_t>(piece)].offset(x);
  return y == 0.0 ? tp.position : Eigen::Vector3d(tp.position + y * tp.left);
}

// Main chainage of point i of a run (i = 0 is its start).
double runChainage(double x0, double x1, std::size_t i, std::size_t n) {
  return i == n ? x1 : x0 + (x1 - x0) * static_cast<double>(i) / static_cast<double>(n);
}

// Points 0..n of run k (0: the previous run's last point, or the first run's point at x0).
void runPoints(const Track& main, const LayoutTrack& track, std::size_t k,
               std::vector<Eigen::Vector3d>& out) {
  const PolylineRun& r = track.runs[k];
  out.clear();
  out.push_back(k == 0 ? pointOf(main, track, r.piece, r.x0)
                       : pointOf(main, track, track.runs[k - 1].piece, track.runs[k - 1].x1));
  for (std::size_t i = 1; i <= r.n; ++i)
    out.push_back(pointOf(main, track, r.piece, runChainage(r.x0, r.x1, i, r.n)));
}

struct PlanBox {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  void add(const Eigen::Vector3d& p) {
    min_x = std::min(min_x, p.x());
    min_y = std::min(min_y, p.y());
    max_x = std::max(max_x, p.x());
    max_y = std::max(max_y, p.y());
  }
  bool meets(const PlanBox& o) const {
    return o.min_x <= max_x && o.max_x >= min_x && o.min_y <= max_y && o.max_y >= min_y;
  }
};

// Plan bounds of every run of every track (indexed like the tracks), made while the layout is
// built or checked and dropped after: the plan keeps only the runs.
using RunBounds = std::vector<std::vector<PlanBox>>;

std::vector<PlanBox> boundsOf(const Track& main, const LayoutTrack& track) {
  std::vector<PlanBox> out;
  std::vector<Eigen::Vector3d> points;
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    runPoints(main, track, k, points);
    PlanBox& box = out.emplace_back();
    for (const Eigen::Vector3d& p : points)
      box.add(p);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Clearance: a uniform plan-view grid over the segments near one track.

double pointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

class SegmentGrid {
 public:
  explicit SegmentGrid(double cell_m) : cell_(cell_m) {}

  // The segments between consecutive `points` of track `track_index`.
  void add(const std::vector<Eigen::Vector3d>& points, int track_index) {
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const Eigen::Vector3d& a = points[i];
      const Eigen::Vector3d& b = points[i + 1];
      const auto index = static_cast<std::uint32_t>(segments_.size());
      segments_.push_back({a, b, track_index});
      const std::int64_t x0 = cellOf(std::min(a.x(), b.x())), x1 = cellOf(std::max(a.x(), b.x()));
      const std::int64_t y0 = cellOf(std::min(a.y(), b.y())), y1 = cellOf(std::max(a.y(), b.y()));
      for (std::int64_t ix = x0; ix <= x1; ++ix)
        for (std::int64_t iy = y0; iy <= y1; ++iy)
          cells_[key(ix, iy)].push_back(index);
    }
  }

  /// Smallest distance from p to a segment of a track other than `exclude`, among segments
  /// within `radius_m` of p in plan (and the track it belongs to); infinity and -1 if none.
  std::pair<double, int> nearest(const Eigen::Vector3d& p, double radius_m, int exclude) const {
    std::pair<double, int> best{std::numeric_limits<double>::infinity(), -1};
    const std::int64_t x0 = cellOf(p.x() - radius_m), x1 = cellOf(p.x() + radius_m);
    const std::int64_t y0 = cellOf(p.y() - radius_m), y1 = cellOf(p.y() + radius_m);
    for (std::int64_t ix = x0; ix <= x1; ++ix) {
      for (std::int64_t iy = y0; iy <= y1; ++iy) {
        const auto it = cells_.find(key(ix, iy));
        if (it == cells_.end())
          continue;
        for (std::uint32_t index : it->second) {
          const Segment& s = segments_[index];
          if (s.track == exclude)
            continue;
          const double dist = pointSegmentDistance(p, s.a, s.b);
          if (dist < best.first)
            best = {dist, s.track};
        }
      }
    }
    return best;
  }

 private:
  struct Segment {
    Eigen::Vector3d a, b;
    int track;
  };
  std::int64_t cellOf(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  static std::uint64_t key(std::int64_t ix, std::int64_t iy) {
    return (static_cast<std::uint64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
  }

  double cell_;
  std::vector<Segment> segments_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

bool inRanges(double u, const std::vector<std::pair<double, double>>& ranges) {
  for (const auto& [a, b] : ranges)
    if (u >= a - 1e-9 && u <= b + 1e-9)
      return true;
  return false;
}

double gridCell(double min_distance_m) {
  return std::max(min_distance_m, 1.0);
}

// Issues of `track` (polyline `own`, id `self`, not necessarily in `tracks` yet) against every
// other track of `tracks` whose runs come within min_distance_m of it in plan.
void collectIssues(const Track& main, const LayoutTrack& track, const Polyline& own, int self,
                   const std::vector<LayoutTrack>& tracks, const RunBounds& bounds,
                   double min_distance_m, std::vector<ClearanceIssue>& out) {
  PlanBox box;
  for (const Eigen::Vector3d& p : own.points)
    box.add(p);
  box.min_x -= min_distance_m;
  box.min_y -= min_distance_m;
  box.max_x += min_distance_m;
  box.max_y += min_distance_m;
  SegmentGrid grid(gridCell(min_distance_m));
  std::vector<Eigen::Vector3d> points;
  for (std::size_t j = 0; j < tracks.size(); ++j) {
    if (static_cast<int>(j) == self)
      continue;
    for (std::size_t k = 0; k < tracks[j].runs.size(); ++k) {
      if (!box.meets(bounds[j][k]))
        continue;
      runPoints(main, tracks[j], k, points);
      grid.add(points, static_cast<int>(j));
    }
  }
  for (std::size_t i = 0; i < own.points.size(); ++i) {
    if (inRanges(own.distance_m[i], track.turnout_ranges_m))
      continue;
    const auto [dist, other] = grid.nearest(own.points[i], min_distance_m, self);
    if (dist < min_distance_m - kClearanceTolerance_m)
      out.push_back(
          {track.id, tracks[static_cast<std::size_t>(other)].id, own.distance_m[i], dist});
  }
}

// ---------------------------------------------------------------------------------------------
// Sampling tracks into runs.

// A stretch of one layout track between two main chainages, with the block it belongs to.
struct Interval {
  double x0 = 0.0, x1 = 0.0;  // main chainage
  LayoutBlockType type = LayoutBlockType::kStraight;
  TrackPart part = TrackPart::kWhole;
  int main_block_id = -1;
  bool in_turnout = false;
  int piece = 0;  // the offset piece that gives the offset
};

// The intervals cut wherever main chainage crosses a multiple of kPolylineRunLength_m, so
// that no run is longer.
std::vector<Interval> cutIntoRuns(const std::vector<Interval>& intervals) {
  std::vector<Interval> out;
  for (const Interval& iv : intervals) {
    double x = iv.x0;
    for (;;) {
      const double grid = (std::floor(x / kPolylineRunLength_m) + 1.0) * kPolylineRunLength_m;
      Interval part = iv;
      part.x0 = x;
      part.x1 = std::min(iv.x1, grid);
      if (iv.x1 - part.x1 <= 1e-9)
        part.x1 = iv.x1;
      out.push_back(part);
      if (part.x1 == iv.x1)
        break;
      x = part.x1;
    }
  }
  return out;
}

// The run for `iv` after the point `p0`: just enough points, uniform in x, for every 3D chord
// to be at most `spacing_m` (re-sampled more finely until it is). `points` receives points
// 0..n of the run.
PolylineRun sampleRun(const Track& main, const LayoutTrack& track, const Interval& iv,
                      const Eigen::Vector3d& p0, double distance_begin_m, double spacing_m,
                      std::vector<Eigen::Vector3d>& points, PlanBox& box) {
  PolylineRun run;
  run.x0 = iv.x0;
  run.x1 = iv.x1;
  run.piece = iv.piece;
  run.distance_begin_m = distance_begin_m;
  const Eigen::Vector3d p1 = pointOf(main, track, iv.piece, iv.x1);
  const double estimate = std::max((p1 - p0).norm(), iv.x1 - iv.x0) * 1.001;
  std::size_t n =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(estimate / spacing_m)));
  for (;;) {
    points.assign(1, p0);
    double max_chord = 0.0;
    for (std::size_t i = 1; i <= n; ++i) {
      const Eigen::Vector3d q =
          i == n ? p1 : pointOf(main, track, iv.piece, runChainage(iv.x0, iv.x1, i, n));
      max_chord = std::max(max_chord, (q - points.back()).norm());
      points.push_back(q);
    }
    if (max_chord <= spacing_m)
      break;
    n = std::max(n + 1, static_cast<std::size_t>(
                            std::ceil(static_cast<double>(n) * max_chord / spacing_m * 1.001)));
  }
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw RuntimeError(fmt::format("layout track {}: {} polyline points in one run", track.id, n));
  run.n = static_cast<std::uint32_t>(n);
  double distance = distance_begin_m;
  box = PlanBox{};
  box.add(points.front());
  for (std::size_t i = 1; i < points.size(); ++i) {
    distance += (points[i] - points[i - 1]).norm();
    box.add(points[i]);
  }
  run.distance_end_m = distance;
  return run;
}

// Fills the track's runs, blocks and turnout ranges from consecutive intervals (its offset
// law already set). Consecutive intervals with the same labels form one block.
void sampleTrack(const Track& main, const std::vector<Interval>& intervals, double spacing_m,
                 LayoutTrack& track, std::vector<PlanBox>* bounds = nullptr) {
  const std::vector<Interval> cut = cutIntoRuns(intervals);
  track.runs.clear();
  track.blocks.clear();
  if (bounds != nullptr)
    bounds->clear();
  track.turnout_ranges_m.clear();
  std::vector<Eigen::Vector3d> points{pointOf(main, track, cut.front().piece, cut.front().x0)};
  for (std::size_t k = 0; k < cut.size(); ++k) {
    const Interval& iv = cut[k];
    const Eigen::Vector3d p0 = points.back();
    PlanBox box;
    track.runs.push_back(sampleRun(main, track, iv, p0, track.length_m(), spacing_m, points, box));
    if (bounds != nullptr)
      bounds->push_back(box);
    const double begin = track.runs.back().distance_begin_m, end = track.runs.back().distance_end_m;
    if (k > 0 && track.blocks.back().type == iv.type && track.blocks.back().part == iv.part &&
        track.blocks.back().main_block_id == iv.main_block_id)
      track.blocks.back().end_m = end;
    else
      track.blocks.push_back({iv.type, iv.part, begin, end, iv.main_block_id});
    if (iv.in_turnout) {
      if (k > 0 && cut[k - 1].in_turnout)
        track.turnout_ranges_m.back().second = end;
      else
        track.turnout_ranges_m.emplace_back(begin, end);
    }
  }
  track.runs.shrink_to_fit();
  track.blocks.shrink_to_fit();
}

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

double OffsetPiece::offset(double x) const {
  if (shape == Shape::kLine)
    return x1 > x0 ? y0 + (y1 - y0) * (x - x0) / (x1 - x0) : y0;
  const double u = x - xt;
  // r − sqrt(r² − u²) without cancellation.
  return yt + bend * u * u / (r + std::sqrt(std::max(0.0, r * r - u * u)));
}

double OffsetPiece::slope(double x) const {
  if (shape == Shape::kLine)
    return x1 > x0 ? (y1 - y0) / (x1 - x0) : 0.0;
  const double u = x - xt;
  return bend * u / std::sqrt(std::max(1e-300, r * r - u * u));
}

OffsetPiece OffsetPiece::line(double x0, double x1, double y0, double y1) {
  OffsetPiece p;
  p.x0 = x0;
  p.x1 = x1;
  p.y0 = y0;
  p.y1 = y1;
  return p;
}

TrackFrame trackFrame(const Track& main, const LayoutTrack& track, double main_chainage_m) {
  if (track.offset.empty())
    throw RuntimeError(fmt::format("layout track {} has no offset law", track.id));
  const double x = std::clamp(main_chainage_m, track.offset.front().x0, track.offset.back().x1);
  const auto piece = std::lower_bound(track.offset.begin(), track.offset.end() - 1, x,
                                      [](const OffsetPiece& p, double v) { return p.x1 < v; });
  const double y = piece->offset(x), dy = piece->slope(x);
  const TrackPoint tp = main.atChainage(x);
  // The main track's horizontal axes (local level) at x.
  const Eigen::Vector3d l_plan = tp.left;
  const Eigen::Vector3d t_plan = l_plan.cross(tp.up);
  // P(x) = main(x) + y(x) l(x), with dl/dx = −κ t and the height from the main track at x.
  const double dz_dx = std::tan(tp.pitch_rad);
  const Eigen::Vector3d dp = (1.0 - tp.curvature_1_m * y) * t_plan + dy * l_plan + dz_dx * tp.up;
  TrackFrame f;
  f.main_chainage_m = x;
  f.position = tp.position + y * l_plan;
  f.tangent = dp.normalized();
  f.roll_rad = tp.roll_rad;
  // Left across the track: level and square to the tangent, then turned by the roll about the
  // tangent (left rail up for positive roll).
  const Eigen::Vector3d level_left = tp.up.cross(f.tangent).normalized();
  f.left = Eigen::AngleAxisd(f.roll_rad, f.tangent) * level_left;
  f.up = f.tangent.cross(f.left);
  return f;
}

TrackFrame trackFrameAtDistance(const Track& main, const LayoutTrack& track, double distance_m) {
  if (track.runs.empty())
    throw RuntimeError(fmt::format("layout track {} has no sampled polyline", track.id));
  const double u = std::clamp(distance_m, 0.0, track.length_m());
  const auto run =
      std::lower_bound(track.runs.begin(), track.runs.end() - 1, u,
                       [](const PolylineRun& r, double v) { return r.distance_end_m < v; });
  const auto k = static_cast<std::size_t>(run - track.runs.begin());
  std::vector<Eigen::Vector3d> points;
  runPoints(main, track, k, points);
  double d0 = run->distance_begin_m;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double d1 =
        i == points.size() - 1 ? run->distance_end_m : d0 + (points[i] - points[i - 1]).norm();
    if (u <= d1 || i == points.size() - 1) {
      const double w = d1 > d0 ? std::clamp((u - d0) / (d1 - d0), 0.0, 1.0) : 0.0;
      const double xa = runChainage(run->x0, run->x1, i - 1, run->n);
      const double xb = runChainage(run->x0, run->x1, i, run->n);
      return trackFrame(main, track, xa + w * (xb - xa));
    }
    d0 = d1;
  }
  return trackFrame(main, track, run->x1);
}

void forEachPolylinePoint(
    const Track& main, const LayoutTrack& track,
    const std::function<void(const Eigen::Vector3d&, double, double)>& visit) {
  std::vector<Eigen::Vector3d> points;
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    const PolylineRun& r = track.runs[k];
    runPoints(main, track, k, points);
    double distance = r.distance_begin_m;
    if (k == 0)
      visit(points.front(), distance, r.x0);
    for (std::size_t i = 1; i < points.size(); ++i) {
      distance += (points[i] - points[i - 1]).norm();
      visit(points[i], distance, runChainage(r.x0, r.x1, i, r.n));
    }
  }
}

Polyline samplePolyline(const Track& main, const LayoutTrack& track, double x_begin, double x_end) {
  Polyline out;
  std::vector<Eigen::Vector3d> points;
  bool have_previous_end = false;  // the last point pushed is the previous run's last point
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    const PolylineRun& r = track.runs[k];
    // Segment i (points i − 1 → i) spans main chainage [x(i − 1), x(i)].
    if (r.x1 < x_begin || r.x0 > x_end) {
      have_previous_end = false;
      continue;
    }
    runPoints(main, track, k, points);
    double distance = r.distance_begin_m;
    bool previous_pushed = have_previous_end;
    for (std::size_t i = 1; i <= r.n; ++i) {
      const double xa = runChainage(r.x0, r.x1, i - 1, r.n), xb = runChainage(r.x0, r.x1, i, r.n);
      const double da = distance;
      distance += (points[i] - points[i - 1]).norm();
      if (xb < x_begin || xa > x_end) {
        previous_pushed = false;
        continue;
      }
      if (!previous_pushed) {
        out.points.push_back(points[i - 1]);
        out.distance_m.push_back(da);
        out.main_chainage_m.push_back(xa);
      }
      out.points.push_back(points[i]);
      out.distance_m.push_back(distance);
      out.main_chainage_m.push_back(xb);
      previous_pushed = true;
    }
    have_previous_end = previous_pushed;
  }
  return out;
}

LayoutTrack offsetTrack(const Track& main, int id, TrackKind kind, std::vector<OffsetPiece> offset,
                        double spacing_m, LayoutBlockType type) {
  if (offset.empty())
    throw RuntimeError(fmt::format("layout track {} has no offset law", id));
  LayoutTrack track;
  track.id = id;
  track.kind = kind;
  track.offset_m = offset.front().offset(offset.front().x0);
  track.main_chainage_begin_m = offset.front().x0;
  track.main_chainage_end_m = offset.back().x1;
  track.offset = std::move(offset);
  std::vector<Interval> intervals;
  for (std::size_t i = 0; i < track.offset.size(); ++i)
    intervals.push_back({track.offset[i].x0, track.offset[i].x1, type, TrackPart::kWhole, -1, false,
                         static_cast<int>(i)});
  sampleTrack(main, intervals, spacing_m, track);
  return track;
}

std::vector<ClearanceIssue> checkClearance(const Track& main, const Layout& layout,
                                           double min_distance_m) {
  std::vector<ClearanceIssue> out;
  if (!(min_distance_m > kClearanceTolerance_m))
    return out;
  RunBounds bounds;
  for (const LayoutTrack& t : layout.tracks)
    bounds.push_back(boundsOf(main, t));
  for (std::size_t i = 0; i < layout.tracks.size(); ++i) {
    const LayoutTrack& t = layout.tracks[i];
    if (t.kind == TrackKind::kAuxiliary)
      collectIssues(main, t, samplePolyline(main, t), static_cast<int>(i), layout.tracks, bounds,
                    min_distance_m, out);
  }
  return out;
}

}  // namespace trainsim::track
