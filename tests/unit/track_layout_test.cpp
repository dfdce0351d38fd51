// Multi-track layout: turnout and dead-end geometry against the closed forms of
// docs/REFERENCES.md R1.5, the double track as an exact normal offset of the main
// centreline, clearance of random layouts over many routes, and the clearance checker itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <Eigen/Geometry>

#include "trainsim/core/error.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route_design.hpp"

namespace trainsim::track {
namespace {

// A single straight of `length` m from `start` at `heading` (level at height z0) with one
// straight block.
Route straightRoute(double length_m, Eigen::Vector2d start, double heading_rad, double z0_m) {
  Block b;
  b.id = 0;
  b.type = BlockType::kStraight;
  b.chainage_end_m = length_m;
  return Route{
      Track(HorizontalAlignment(start, heading_rad, {HorizontalElement::straight(length_m)}),
            VerticalProfile(length_m, z0_m), CantProfile()),
      {b}};
}

// Along-track and lateral (+ left) coordinates of q relative to a straight main track.
struct Frame {
  Eigen::Vector2d origin, t, n;
  Eigen::Vector2d local(const Eigen::Vector3d& q) const {
    const Eigen::Vector2d v = q.head<2>() - origin;
    return {v.dot(t), v.dot(n)};
  }
};

Frame frameOf(const Eigen::Vector2d& start, double heading) {
  return {start, {std::cos(heading), std::sin(heading)}, {-std::sin(heading), std::cos(heading)}};
}

std::size_t indexAt(const Polyline& line, double distance) {
  const auto it = std::lower_bound(line.distance_m.begin(), line.distance_m.end(), distance - 1e-9);
  return static_cast<std::size_t>(it - line.distance_m.begin());
}

double blockLength(const LayoutBlock& b) {
  return b.end_m - b.begin_m;
}

constexpr double kD = 4.0;

TEST(Layout, KnownTurnouts) {
  const Turnout t = turnoutGeometry(*enumFromName<TurnoutType>("190-1:9"));
  EXPECT_DOUBLE_EQ(t.radius_m, 190.0);
  EXPECT_DOUBLE_EQ(t.ratio, 9.0);
  EXPECT_DOUBLE_EQ(turnoutGeometry(*enumFromName<TurnoutType>("500-1:12")).radius_m, 500.0);
  EXPECT_FALSE(enumFromName<TurnoutType>("300-1:9"));
}

TEST(Layout, TurnoutConnectionReachesTrackCentreDistanceAndTurnsBackParallel) {
  // Reference values (docs/REFERENCES.md R1.5): 190-1:9 at d = 4.0 m: L_s ≈ 15.2 m, L_x ≈ 57 m.
  const double r = 190.0, alpha = std::atan(1.0 / 9.0);
  const double ls = (kD - 2.0 * r * (1.0 - std::cos(alpha))) / std::sin(alpha);
  const double lx = 2.0 * r * std::sin(alpha) + ls * std::cos(alpha);
  EXPECT_NEAR(ls, 15.2, 0.05);
  EXPECT_NEAR(lx, 57.0, 0.1);

  const Eigen::Vector2d start(100.0, -50.0);
  const double heading = 0.3;
  const Route route = straightRoute(3000.0, start, heading, 12.0);
  LayoutParams p;
  p.double_track = false;
  p.side = AuxSide::kLeft;
  p.aux_probability = 1.0;
  p.turnout_probability = 1.0;
  p.aux_parallel_min_m = p.aux_parallel_max_m = 300.0;
  const Layout layout = buildLayout(route, p, 7);
  ASSERT_GE(layout.tracks.size(), 2u);
  const LayoutTrack& aux = layout.tracks[1];
  EXPECT_EQ(aux.kind, TrackKind::kAuxiliary);
  EXPECT_EQ(aux.joins_track, 0);
  EXPECT_DOUBLE_EQ(aux.offset_m, kD);
  ASSERT_EQ(aux.turnout_ranges_m.size(), 2u);

  const Frame f = frameOf(start, heading);
  const Polyline line = samplePolyline(route.track, aux);
  const std::vector<Eigen::Vector3d>& pl = line.points;
  // Entering: leaves the main track tangentially on a circle of radius R ...
  const Eigen::Vector2d toe = f.local(pl.front());
  EXPECT_NEAR(toe.y(), 0.0, 1e-9);
  const Eigen::Vector2d centre = toe + Eigen::Vector2d(0.0, r);
  int on_arc = 0;
  for (const Eigen::Vector3d& q : pl) {
    const Eigen::Vector2d l = f.local(q);
    if (l.x() - toe.x() > r * std::sin(alpha) + 1e-9)
      break;
    EXPECT_NEAR((l - centre).norm(), r, 1e-9);
    ++on_arc;
  }
  EXPECT_GE(on_arc, 10);
  // ... the diverging arc plus the diagonal make the "turnout" block ...
  ASSERT_GE(aux.blocks.size(), 5u);
  EXPECT_EQ(aux.blocks[0].type, LayoutBlockType::kTurnout);
  EXPECT_EQ(aux.blocks[0].part, TrackPart::kEntering);
  EXPECT_NEAR(blockLength(aux.blocks[0]) - r * alpha, ls, 1e-3);  // chords vs arc: ~1e-4 m
  EXPECT_EQ(aux.blocks[1].type, LayoutBlockType::kCurve);
  EXPECT_EQ(aux.blocks[2].type, LayoutBlockType::kParallel);
  // ... and reaches exactly d, parallel to the main track, L_x further on.
  const std::size_t i_end = indexAt(line, aux.turnout_ranges_m[0].second);
  const Eigen::Vector2d end = f.local(pl[i_end]);
  EXPECT_NEAR(end.y(), kD, 1e-9);
  EXPECT_NEAR(end.x() - toe.x(), lx, 1e-9);
  const Eigen::Vector2d next = f.local(pl[i_end + 1]) - end;
  EXPECT_NEAR(std::atan2(next.y(), next.x()), 0.0, 1e-9);
  // The parallel part stays at d; the track is level at the main track's height.
  for (std::size_t i = i_end; i < pl.size(); ++i) {
    EXPECT_NEAR(pl[i].z(), 12.0, 1e-12);
    if (line.distance_m[i] > aux.turnout_ranges_m[1].first + 1e-9)
      break;
    EXPECT_NEAR(f.local(pl[i]).y(), kD, 1e-9);
  }
  // Outgoing: the mirror image, ending on the main track.
  EXPECT_EQ(aux.blocks.back().type, LayoutBlockType::kTurnout);
  EXPECT_EQ(aux.blocks.back().part, TrackPart::kOutgoing);
  const std::size_t i_out = indexAt(line, aux.turnout_ranges_m[1].first);
  EXPECT_NEAR(f.local(pl.back()).y(), 0.0, 1e-9);
  EXPECT_NEAR(f.local(pl.back()).x() - f.local(pl[i_out]).x(), lx, 1e-9);
  EXPECT_NEAR(aux.turnout_ranges_m[1].second, line.distance_m.back(), 1e-12);
  EXPECT_NEAR(aux.length_m(), line.distance_m.back(), 1e-12);
  EXPECT_NEAR(aux.main_chainage_end_m - aux.main_chainage_begin_m,
              2.0 * lx + (aux.turnout_ranges_m[1].first - aux.turnout_ranges_m[0].second), 1e-6);
}

TEST(Layout, DeadEndLiesOutsideTheParallelPart) {
  const double r = 190.0, alpha = std::atan(1.0 / 9.0), dead_end = 40.0;
  const Eigen::Vector2d start(-20.0, 300.0);
  const double heading = -1.2;
  const Route route = straightRoute(2000.0, start, heading, 0.0);
  LayoutParams p;
  p.double_track = true;
  p.side = AuxSide::kRight;
  p.aux_probability = 1.0;
  p.turnout_probability = 0.0;
  p.dead_end_length_m = dead_end;
  const Layout layout = buildLayout(route, p, 11);
  ASSERT_GE(layout.tracks.size(), 3u);
  const LayoutTrack& aux = layout.tracks[2];
  EXPECT_EQ(aux.joins_track, -1);  // no turnout connects it
  EXPECT_DOUBLE_EQ(aux.offset_m, -2.0 * kD);
  EXPECT_TRUE(aux.turnout_ranges_m.empty());
  ASSERT_EQ(aux.blocks.size(), 5u);
  EXPECT_EQ(aux.blocks[0].type, LayoutBlockType::kDeadEnd);
  EXPECT_EQ(aux.blocks[1].type, LayoutBlockType::kCurve);
  EXPECT_EQ(aux.blocks[4].type, LayoutBlockType::kDeadEnd);
  EXPECT_NEAR(blockLength(aux.blocks[0]), dead_end, 1e-9);
  EXPECT_NEAR(blockLength(aux.blocks[4]), dead_end, 1e-9);
  const Frame f = frameOf(start, heading);
  const Polyline line = samplePolyline(route.track, aux);
  const double buffer = -2.0 * kD - (dead_end * std::sin(alpha) + r * (1.0 - std::cos(alpha)));
  EXPECT_NEAR(f.local(line.points.front()).y(), buffer, 1e-9);
  EXPECT_NEAR(f.local(line.points.back()).y(), buffer, 1e-9);
  const std::size_t i = indexAt(line, aux.blocks[2].begin_m);
  EXPECT_NEAR(f.local(line.points[i]).y(), -2.0 * kD, 1e-9);
  const Eigen::Vector2d step = f.local(line.points[i + 1]) - f.local(line.points[i]);
  EXPECT_NEAR(std::atan2(step.y(), step.x()), 0.0, 1e-9);
  EXPECT_TRUE(checkClearance(route.track, layout, kD).empty());
}

TEST(Layout, DoubleTrackIsTheNormalOffsetOnTheRight) {
  const DesignedRoute designed = generateRoute(RouteGeneratorParams{}, RouteOptions{}, 3);
  const Route& route = designed.route;
  LayoutParams p;
  p.aux_probability = 0.0;
  const Layout layout = buildLayout(route, p, 1);
  ASSERT_EQ(layout.tracks.size(), 2u);
  const LayoutTrack& main = layout.tracks[0];
  const LayoutTrack& dbl = layout.tracks[1];
  EXPECT_EQ(main.kind, TrackKind::kMain);
  EXPECT_EQ(dbl.kind, TrackKind::kDouble);
  EXPECT_DOUBLE_EQ(dbl.offset_m, -kD);
  ASSERT_EQ(main.blocks.size(), route.blocks.size());
  ASSERT_EQ(dbl.blocks.size(), route.blocks.size());
  for (std::size_t k = 0; k < route.blocks.size(); ++k) {
    EXPECT_EQ(main.blocks[k].type, layoutBlockType(route.blocks[k].type));
    EXPECT_EQ(dbl.blocks[k].type, main.blocks[k].type);
    EXPECT_EQ(dbl.blocks[k].main_block_id, route.blocks[k].id);
  }
  const HorizontalAlignment& h = route.track.horizontal();
  bool curved = false;
  const Polyline main_line = samplePolyline(route.track, main);
  const Polyline dbl_line = samplePolyline(route.track, dbl);
  for (const Polyline* t : {&main_line, &dbl_line}) {
    ASSERT_EQ(t->points.size(), t->distance_m.size());
    for (std::size_t i = 1; i < t->points.size(); ++i)
      ASSERT_LE((t->points[i] - t->points[i - 1]).norm(), p.polyline_spacing_m + 1e-12);
  }
  // Nearest point of the exact main centreline (golden-section search on chainage around the
  // nearest main polyline point): at distance d, on the right, at the same height.
  std::size_t j = 0;
  for (const Eigen::Vector3d& q : dbl_line.points) {
    while (j + 1 < main_line.points.size() &&
           (main_line.points[j + 1] - q).norm() <= (main_line.points[j] - q).norm())
      ++j;
    const auto dist = [&](double s) { return (h.at(s).position_m - q.head<2>()).norm(); };
    double a = std::max(0.0, main_line.main_chainage_m[j] - 5.0);
    double b = std::min(h.length(), main_line.main_chainage_m[j] + 5.0);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    while (b - a > 1e-10) {
      const double c = b - g * (b - a), e = a + g * (b - a);
      if (dist(c) < dist(e))
        b = e;
      else
        a = c;
    }
    const double s = 0.5 * (a + b);
    const HorizontalState st = h.at(s);
    EXPECT_NEAR(dist(s), kD, 1e-6) << s;
    const Eigen::Vector2d v = q.head<2>() - st.position_m;
    EXPECT_LT(std::cos(st.heading_rad) * v.y() - std::sin(st.heading_rad) * v.x(), 0.0) << s;
    EXPECT_NEAR(q.z(), route.track.atChainage(s).position.z(), 1e-6) << s;
    curved = curved || st.curvature_1_m != 0.0;
  }
  EXPECT_TRUE(curved);
}

TEST(Layout, RandomLayoutsKeepClearanceOverManyRoutes) {
  int aux_tracks = 0, turnout_ends = 0, dead_ends = 0, left = 0, right = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const Route route = generateRoute(RouteGeneratorParams{}, RouteOptions{}, seed).route;
    LayoutParams p;
    p.aux_probability = 0.8;
    p.double_track = seed % 3 != 0;
    const Layout layout = buildLayout(route, p, seed);
    const std::vector<ClearanceIssue> issues = checkClearance(route.track, layout, kD);
    ASSERT_TRUE(issues.empty()) << "seed " << seed << ": track " << issues[0].track_id << " at "
                                << issues[0].distance_along_m << " m is " << issues[0].clearance_m
                                << " m from track " << issues[0].other_track_id;
    const HorizontalAlignment& h = route.track.horizontal();
    std::map<double, std::pair<double, double>> by_side;  // offset -> last chainage range
    for (std::size_t i = 0; i < layout.tracks.size(); ++i) {
      const LayoutTrack& t = layout.tracks[i];
      ASSERT_EQ(t.id, static_cast<int>(i));
      if (t.kind != TrackKind::kAuxiliary)
        continue;
      ++aux_tracks;
      (t.offset_m > 0.0 ? left : right) += 1;
      // Beside a straight of the main track, never alongside a tunnel or bridge.
      const std::size_t e = h.elementAt(0.5 * (t.main_chainage_begin_m + t.main_chainage_end_m));
      EXPECT_EQ(h.elements()[e].type, HorizontalElement::Type::kStraight);
      EXPECT_LE(h.elementStart(e), t.main_chainage_begin_m + 1e-9) << "seed " << seed;
      EXPECT_GE(h.elementStart(e + 1), t.main_chainage_end_m - 1e-9) << "seed " << seed;
      for (const LayoutBlock& b : t.blocks) {
        ASSERT_GE(b.main_block_id, 0);
        const BlockType type = route.blocks[static_cast<std::size_t>(b.main_block_id)].type;
        EXPECT_TRUE(type == BlockType::kStraight || type == BlockType::kStation);
      }
      const double expected_offset = t.offset_m > 0.0 ? kD : (p.double_track ? -2.0 * kD : -kD);
      EXPECT_DOUBLE_EQ(t.offset_m, expected_offset);
      // The parallel part, measured against the exact main centreline.
      const HorizontalState s0 = h.at(t.main_chainage_begin_m);
      const Frame f = frameOf(s0.position_m, s0.heading_rad);
      int parallel_points = 0;
      const Polyline line = samplePolyline(route.track, t);
      for (const LayoutBlock& b : t.blocks) {
        if (b.type != LayoutBlockType::kParallel)
          continue;
        for (std::size_t k = indexAt(line, b.begin_m); k < line.points.size(); ++k) {
          if (line.distance_m[k] > b.end_m + 1e-9)
            break;
          EXPECT_NEAR(f.local(line.points[k]).y(), t.offset_m, 1e-6);
          ++parallel_points;
        }
      }
      EXPECT_GE(parallel_points, 150);  // at least 300 m at 2 m spacing
      const bool turnout_begin = t.blocks.front().type == LayoutBlockType::kTurnout;
      const bool turnout_end = t.blocks.back().type == LayoutBlockType::kTurnout;
      EXPECT_TRUE(turnout_begin || t.blocks.front().type == LayoutBlockType::kDeadEnd);
      EXPECT_TRUE(turnout_end || t.blocks.back().type == LayoutBlockType::kDeadEnd);
      turnout_ends += turnout_begin + turnout_end;
      dead_ends += !turnout_begin + !turnout_end;
      EXPECT_EQ(t.turnout_ranges_m.size(), static_cast<std::size_t>(turnout_begin + turnout_end));
      const int neighbour = t.offset_m < -kD ? 1 : 0;
      EXPECT_EQ(t.joins_track, turnout_begin || turnout_end ? neighbour : -1);
      // Same side: no overlap, 20 m apart.
      const auto prev = by_side.find(t.offset_m);
      if (prev != by_side.end()) {
        const bool apart = t.main_chainage_begin_m >= prev->second.second + 20.0 - 1e-9 ||
                           t.main_chainage_end_m <= prev->second.first - 20.0 + 1e-9;
        EXPECT_TRUE(apart) << "seed " << seed;
      }
      by_side[t.offset_m] = {t.main_chainage_begin_m, t.main_chainage_end_m};
    }
  }
  EXPECT_GT(aux_tracks, 100);
  EXPECT_GT(turnout_ends, 0);
  EXPECT_GT(dead_ends, 0);
  EXPECT_GT(left, 0);
  EXPECT_GT(right, 0);
}

TEST(Layout, SameInputsGiveTheSameLayout) {
  const Route route = generateRoute(RouteGeneratorParams{}, RouteOptions{}, 5).route;
  LayoutParams p;
  p.aux_probability = 0.8;
  const Layout a = buildLayout(route, p, 42), b = buildLayout(route, p, 42);
  ASSERT_EQ(a.tracks.size(), b.tracks.size());
  for (std::size_t i = 0; i < a.tracks.size(); ++i)
    EXPECT_EQ(samplePolyline(route.track, a.tracks[i]).points,
              samplePolyline(route.track, b.tracks[i]).points);
}

// A hand-built layout: a straight level main track along x (z = 5) sampled every
// `main_step_m`, and one auxiliary track beside it from x = 50 to 150 at `aux_offset_m`, every 2 m.
struct HandLayout {
  Route route = straightRoute(200.0, {0.0, 0.0}, 0.0, 5.0);
  Layout layout;
};

HandLayout handLayout(double aux_offset_m, double main_step_m) {
  HandLayout h;
  const Track& main = h.route.track;
  h.layout.tracks = {
      offsetTrack(main, 0, TrackKind::kMain, {OffsetPiece::line(0.0, 200.0, 0.0, 0.0)},
                  main_step_m),
      offsetTrack(main, 1, TrackKind::kAuxiliary,
                  {OffsetPiece::line(50.0, 150.0, aux_offset_m, aux_offset_m)}, 2.0)};
  return h;
}

std::vector<ClearanceIssue> clearanceOf(const HandLayout& h) {
  return checkClearance(h.route.track, h.layout, kD);
}

TEST(Layout, ClearanceCheckFindsMisplacedTrack) {
  EXPECT_TRUE(clearanceOf(handLayout(kD, 2.0)).empty());
  const HandLayout close = handLayout(0.5 * kD, 2.0);
  const Polyline aux = samplePolyline(close.route.track, close.layout.tracks[1]);
  const std::size_t n = aux.points.size();
  ASSERT_GE(n, 51u);
  const std::vector<ClearanceIssue> issues = clearanceOf(close);
  ASSERT_EQ(issues.size(), n);
  for (const ClearanceIssue& c : issues) {
    EXPECT_EQ(c.track_id, 1);
    EXPECT_EQ(c.other_track_id, 0);
    EXPECT_NEAR(c.clearance_m, 0.5 * kD, 1e-12);
  }
  // Segment distance, not point distance: main points about 67 m apart, so that only a few
  // auxiliary points lie within kD of one.
  const HandLayout sparse = handLayout(0.5 * kD, 100.0);
  ASSERT_LE(samplePolyline(sparse.route.track, sparse.layout.tracks[0]).points.size(), 4u);
  EXPECT_EQ(clearanceOf(sparse).size(), n);
  // Points inside a turnout range are exempt.
  HandLayout h = handLayout(0.5 * kD, 2.0);
  h.layout.tracks[1].turnout_ranges_m = {{0.0, 20.0}, {90.0, 100.0}};
  const auto exempt = std::count_if(aux.distance_m.begin(), aux.distance_m.end(),
                                    [](double u) { return u <= 20.0 + 1e-9 || u >= 90.0 - 1e-9; });
  EXPECT_GE(exempt, 15);
  EXPECT_EQ(clearanceOf(h).size(), n - static_cast<std::size_t>(exempt));
}

// A stretch of the polyline made on demand is the same points, distances and chainages as the
// whole polyline, and the runs' bounds hold their points.
TEST(Layout, PolylineWindowsAgreeWithTheWholePolyline) {
  RouteGeneratorParams g;
  g.length_m = 6000.0;
  const Route route = generateRoute(g, RouteOptions{}, 9).route;
  LayoutParams p;
  p.aux_probability = 1.0;
  const Layout layout = buildLayout(route, p, 3);
  for (const LayoutTrack& t : layout.tracks) {
    const Polyline whole = samplePolyline(route.track, t);
    std::size_t visited = 0;
    forEachPolylinePoint(route.track, t, [&](const Eigen::Vector3d& q, double u, double x) {
      ASSERT_LT(visited, whole.points.size());
      EXPECT_EQ(q, whole.points[visited]);
      EXPECT_EQ(u, whole.distance_m[visited]);
      EXPECT_EQ(x, whole.main_chainage_m[visited]);
      ++visited;
    });
    EXPECT_EQ(visited, whole.points.size());
    EXPECT_NEAR(whole.distance_m.back(), t.length_m(), 1e-9);
    for (const PolylineRun& r : t.runs)
      EXPECT_LE(r.x1 - r.x0, kPolylineRunLength_m + 1e-9);
    const double a =
        t.main_chainage_begin_m + 0.3 * (t.main_chainage_end_m - t.main_chainage_begin_m);
    const double b =
        t.main_chainage_begin_m + 0.7 * (t.main_chainage_end_m - t.main_chainage_begin_m);
    const Polyline part = samplePolyline(route.track, t, a, b);
    ASSERT_GE(part.points.size(), 2u);
    EXPECT_LE(part.main_chainage_m.front(), a);
    EXPECT_GE(part.main_chainage_m.back(), b);
    EXPECT_GT(part.main_chainage_m[1], a);
    EXPECT_LT(part.main_chainage_m[part.points.size() - 2], b);
    const auto first = std::find(whole.points.begin(), whole.points.end(), part.points.front());
    ASSERT_NE(first, whole.points.end());
    const auto offset = static_cast<std::size_t>(first - whole.points.begin());
    for (std::size_t i = 0; i < part.points.size(); ++i) {
      EXPECT_EQ(part.points[i], whole.points[offset + i]);
      EXPECT_EQ(part.distance_m[i], whole.distance_m[offset + i]);
    }
  }
}

TEST(Layout, RejectsTrackCentreDistanceTooSmallForTurnout) {
  const Route route = straightRoute(2000.0, {0.0, 0.0}, 0.0, 0.0);
  LayoutParams p;
  p.turnout = TurnoutType::k500_1_12;
  p.track_centre_distance_m = 3.0;  // 500-1:12 needs 2R(1 − cos α) = 3.45 m
  try {
    buildLayout(route, p, 1);
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("layout.track_centre_distance_m"), std::string::npos)
        << e.what();
  }
  p.track_centre_distance_m = 3.5;
  EXPECT_NO_THROW(buildLayout(route, p, 1));
}

// The frame along every track (main, double, auxiliary) against independent references: the
// main track's own closed forms, the polyline points (P at their chainage), a central finite
// difference of P for the tangent, and orthonormality.
TEST(TrackFrame, AlongEveryTrackMatchesTheTrackAndItsPolyline) {
  RouteGeneratorParams g;
  g.length_m = 4000.0;
  const DesignedRoute designed = generateRoute(g, RouteOptions{}, 5);
  const Route& route = designed.route;
  LayoutParams p;
  p.aux_probability = 1.0;
  const Layout layout = buildLayout(route, p, 2);
  bool aux = false, canted = false;
  for (const LayoutTrack& t : layout.tracks) {
    aux = aux || t.kind == TrackKind::kAuxiliary;
    const Polyline line = samplePolyline(route.track, t);
    ASSERT_EQ(line.main_chainage_m.size(), line.points.size());
    for (std::size_t i = 0; i < line.points.size(); i += 7) {
      const double x = line.main_chainage_m[i];
      const TrackFrame f = trackFrame(route.track, t, x);
      EXPECT_LT((f.position - line.points[i]).norm(), 1e-9) << "track " << t.id << " point " << i;
      // Orthonormal, right-handed.
      EXPECT_NEAR(f.tangent.norm(), 1.0, 1e-12);
      EXPECT_NEAR(f.left.norm(), 1.0, 1e-12);
      EXPECT_NEAR(f.tangent.dot(f.left), 0.0, 1e-12);
      EXPECT_LT((f.up - f.tangent.cross(f.left)).norm(), 1e-12);
      // The tangent is the direction of dP/dx (central difference, h = 10 µm: at a joint of a
      // line and an arc the difference sees half the arc's curvature, an error of h/(2R)).
      const double h = 1e-5;
      if (x - h > t.main_chainage_begin_m && x + h < t.main_chainage_end_m) {
        const Eigen::Vector3d fd = (trackFrame(route.track, t, x + h).position -
                                    trackFrame(route.track, t, x - h).position)
                                       .normalized();
        EXPECT_LT((fd - f.tangent).norm(), 1e-6) << "track " << t.id << " at x " << x;
      }
      // Roll: the main track's at the same chainage, turning left about the tangent.
      const TrackPoint tp = route.track.atChainage(x);
      EXPECT_NEAR(f.roll_rad, tp.roll_rad, 1e-15);
      EXPECT_NEAR(std::asin(f.left.z()), tp.roll_rad, 1e-6);
      canted = canted || std::abs(tp.roll_rad) > 0.01;
      if (t.kind == TrackKind::kMain) {
        EXPECT_LT((f.position - tp.position).norm(), 1e-12);
        EXPECT_LT((f.tangent - tp.d1.normalized()).norm(), 1e-9);
      }
    }
    // By distance along the polyline: the same frame at the polyline's points.
    for (const std::size_t i :
         {std::size_t{0}, line.points.size() / 3, line.points.size() / 2, line.points.size() - 1})
      EXPECT_LT((trackFrameAtDistance(route.track, t, line.distance_m[i]).position - line.points[i])
                    .norm(),
                1e-9);
  }
  EXPECT_TRUE(aux) << "the test route should hold an auxiliary track";
  EXPECT_TRUE(canted) << "the test route should hold a canted curve";
}

}  // namespace
}  // namespace trainsim::track
