// Layout tracks as offset laws from the main track and the runs that sample them: the points,
// frames and polylines made on demand, the sampling itself, and the clearance check.

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "layout_track.hpp"
#include "trainsim/core/error.hpp"

namespace trainsim::track {
namespace {

using detail::Interval;
using detail::PlanBox;

constexpr double kClearanceTolerance_m = 1e-6;

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

// Points 0..n of one run (0: the previous run's last point, or the first run's point at x0),
// with their along-polyline distance and main chainage: every walker of a polyline reads them
// from here, so all agree bit for bit.
struct RunSample {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> distance_m, chainage_m;
};

void sampleRunPoints(const Track& main, const LayoutTrack& track, std::size_t k, RunSample& out) {
  const PolylineRun& r = track.runs[k];
  out.points.clear();
  out.distance_m.clear();
  out.chainage_m.clear();
  out.points.push_back(k == 0
                           ? pointOf(main, track, r.piece, r.x0)
                           : pointOf(main, track, track.runs[k - 1].piece, track.runs[k - 1].x1));
  out.distance_m.push_back(r.distance_begin_m);
  out.chainage_m.push_back(r.x0);
  for (std::size_t i = 1; i <= r.n; ++i) {
    out.chainage_m.push_back(runChainage(r.x0, r.x1, i, r.n));
    out.points.push_back(pointOf(main, track, r.piece, out.chainage_m.back()));
    out.distance_m.push_back(out.distance_m.back() + (out.points[i] - out.points[i - 1]).norm());
  }
}

std::vector<PlanBox> boundsOf(const Track& main, const LayoutTrack& track) {
  std::vector<PlanBox> out;
  RunSample run;
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    sampleRunPoints(main, track, k, run);
    PlanBox& box = out.emplace_back();
    for (const Eigen::Vector3d& p : run.points)
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

// ---------------------------------------------------------------------------------------------
// Sampling tracks into runs.

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

}  // namespace

namespace detail {

void PlanBox::add(const Eigen::Vector3d& p) {
  min_x = std::min(min_x, p.x());
  min_y = std::min(min_y, p.y());
  max_x = std::max(max_x, p.x());
  max_y = std::max(max_y, p.y());
}

void PlanBox::inflate(double margin_m) {
  min_x -= margin_m;
  min_y -= margin_m;
  max_x += margin_m;
  max_y += margin_m;
}

bool PlanBox::meets(const PlanBox& o) const {
  return o.min_x <= max_x && o.max_x >= min_x && o.min_y <= max_y && o.max_y >= min_y;
}

void sampleTrack(const Track& main, const std::vector<Interval>& intervals, double spacing_m,
                 LayoutTrack& track, std::vector<PlanBox>* bounds) {
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

void collectIssues(const Track& main, const LayoutTrack& track, const Polyline& own, int self,
                   const std::vector<LayoutTrack>& tracks, const RunBounds& bounds,
                   double min_distance_m, std::vector<ClearanceIssue>& out) {
  PlanBox box;
  for (const Eigen::Vector3d& p : own.points)
    box.add(p);
  box.inflate(min_distance_m);
  SegmentGrid grid(gridCell(min_distance_m));
  RunSample run;
  for (std::size_t j = 0; j < tracks.size(); ++j) {
    if (static_cast<int>(j) == self)
      continue;
    for (std::size_t k = 0; k < tracks[j].runs.size(); ++k) {
      if (!box.meets(bounds[j][k]))
        continue;
      sampleRunPoints(main, tracks[j], k, run);
      grid.add(run.points, static_cast<int>(j));
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

}  // namespace detail

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
  RunSample s;
  sampleRunPoints(main, track, static_cast<std::size_t>(run - track.runs.begin()), s);
  const auto next = std::lower_bound(s.distance_m.begin() + 1, s.distance_m.end() - 1, u);
  const auto i = static_cast<std::size_t>(next - s.distance_m.begin());
  const double d0 = s.distance_m[i - 1], d1 = s.distance_m[i];
  const double w = d1 > d0 ? std::clamp((u - d0) / (d1 - d0), 0.0, 1.0) : 0.0;
  return trackFrame(main, track, s.chainage_m[i - 1] + w * (s.chainage_m[i] - s.chainage_m[i - 1]));
}

void forEachPolylinePoint(
    const Track& main, const LayoutTrack& track,
    const std::function<void(const Eigen::Vector3d&, double, double)>& visit) {
  RunSample run;
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    sampleRunPoints(main, track, k, run);
    for (std::size_t i = k == 0 ? 0 : 1; i < run.points.size(); ++i)
      visit(run.points[i], run.distance_m[i], run.chainage_m[i]);
  }
}

Polyline samplePolyline(const Track& main, const LayoutTrack& track, double x_begin, double x_end) {
  // Segment i (points i − 1 → i) is in when it reaches [x_begin, x_end]; its first point is
  // added unless the segment before it was in too.
  Polyline out;
  RunSample run;
  bool previous_in = false;
  const auto push = [&](std::size_t i) {
    out.points.push_back(run.points[i]);
    out.distance_m.push_back(run.distance_m[i]);
    out.main_chainage_m.push_back(run.chainage_m[i]);
  };
  for (std::size_t k = 0; k < track.runs.size(); ++k) {
    const PolylineRun& r = track.runs[k];
    if (r.x1 < x_begin || r.x0 > x_end) {
      previous_in = false;
      continue;
    }
    sampleRunPoints(main, track, k, run);
    for (std::size_t i = 1; i < run.points.size(); ++i) {
      if (run.chainage_m[i] < x_begin || run.chainage_m[i - 1] > x_end) {
        previous_in = false;
        continue;
      }
      if (!previous_in)
        push(i - 1);
      push(i);
      previous_in = true;
    }
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
  std::vector<detail::Interval> intervals;
  for (std::size_t i = 0; i < track.offset.size(); ++i)
    intervals.push_back({track.offset[i].x0, track.offset[i].x1, type, TrackPart::kWhole, -1, false,
                         static_cast<int>(i)});
  detail::sampleTrack(main, intervals, spacing_m, track);
  return track;
}

std::vector<ClearanceIssue> checkClearance(const Track& main, const Layout& layout,
                                           double min_distance_m) {
  std::vector<ClearanceIssue> out;
  if (!(min_distance_m > kClearanceTolerance_m))
    return out;
  detail::RunBounds bounds;
  for (const LayoutTrack& t : layout.tracks)
    bounds.push_back(boundsOf(main, t));
  for (std::size_t i = 0; i < layout.tracks.size(); ++i) {
    const LayoutTrack& t = layout.tracks[i];
    if (t.kind == TrackKind::kAuxiliary)
      detail::collectIssues(main, t, samplePolyline(main, t), static_cast<int>(i), layout.tracks,
                            bounds, min_distance_m, out);
  }
  return out;
}

}  // namespace trainsim::track
