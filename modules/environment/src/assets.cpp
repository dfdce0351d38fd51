#include "assets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include "trainsim/core/random.hpp"

namespace trainsim::environment {

const RailProfile& rail60E1() {
  // Half of the 60E1 section (EN 13674-1; sensors-reference.md §5.1: H 172, B 150, C 72,
  // D 16.5, head depth 51, foot depth 31.5 mm), outer side, from the crown's centre down to the
  // foot's centre, in mm. The crown approximates the R300/R80/R13 radii by chords of ≤ 1 mm
  // sagitta; the foot is simplified (it is hidden under the fastenings and in the ballast's
  // shadow).
  static const RailProfile profile = [] {
    const double half[][2] = {{0, 0},       {8, -0.1},   {16, -0.45},  {24, -1.1},     {30, -2.4},
                              {33.5, -4.5}, {35.5, -8},  {36, -14},    {36, -37.5},    {33, -40.5},
                              {12, -46.5},  {8.25, -51}, {8.25, -125}, {10.5, -130.5}, {20, -134},
                              {75, -159.5}, {75, -172},  {0, -172}};
    constexpr int n = sizeof half / sizeof half[0];
    constexpr int head_end = 9;  // edges 0..8 (crown and head side) are the running head
    RailProfile p;
    // Outer half top to bottom, then the inner half (mirrored) bottom to top.
    for (int i = 0; i < n; ++i)
      p.points.emplace_back(half[i][0] * 1e-3, half[i][1] * 1e-3);
    for (int i = n - 2; i > 0; --i)
      p.points.emplace_back(-half[i][0] * 1e-3, half[i][1] * 1e-3);
    for (std::size_t e = 0; e < p.points.size(); ++e) {
      const bool outer_head = e < static_cast<std::size_t>(head_end);
      const bool inner_head = e >= p.points.size() - static_cast<std::size_t>(head_end);
      p.head.push_back(outer_head || inner_head);
    }
    return p;
  }();
  return profile;
}

namespace {

// The profile inclined by tan β = inclination toward the track (top leaning inward, outward
// = +a), then lifted so its highest point is z = 0 (the running surface).
std::vector<Eigen::Vector2d> inclinedProfile(double inclination) {
  const double beta = std::atan(inclination);
  const double c = std::cos(beta), s = std::sin(beta);
  std::vector<Eigen::Vector2d> out;
  double top = -1.0;
  for (const auto& p : rail60E1().points) {
    out.emplace_back(p.x() * c - p.y() * s, p.x() * s + p.y() * c);
    top = std::max(top, out.back().y());
  }
  for (auto& p : out)
    p.y() -= top;
  return out;
}

}  // namespace

double gaugeFaceOffset(double inclination) {
  // The innermost point of the profile's edges crossing z = −14 mm.
  const auto p = inclinedProfile(inclination);
  double inner = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    const double z = -0.014;
    if ((a.y() - z) * (b.y() - z) > 0.0 || a.y() == b.y())
      continue;
    const double t = (z - a.y()) / (b.y() - a.y());
    inner = std::min(inner, a.x() + t * (b.x() - a.x()));
  }
  return -inner;
}

namespace detail {

std::vector<std::vector<FramePoint>> ownedRuns(const TileContext& ctx, int track, double x0,
                                               double x1, double reach_m) {
  std::vector<std::vector<FramePoint>> runs;
  const terrain::Railway& railway = ctx.env.railway();
  for (const terrain::Stretch& s : railway.stretchesNear(ctx.lo, ctx.hi, 10.0)) {
    if (s.track != track || s.x1 < x0 || s.x0 > x1)
      continue;
    const track::Polyline line = railway.polyline(s);
    std::vector<FramePoint> run;
    const auto frame_point = [&](std::size_t k) {
      const track::TrackFrame f = railway.frame(track, line.main_chainage_m[k]);
      return FramePoint{line.points[k], f.tangent,          f.left,
                        f.up,           line.distance_m[k], line.main_chainage_m[k]};
    };
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
      const Eigen::Vector3d mid = 0.5 * (line.points[k] + line.points[k + 1]);
      const double xm = 0.5 * (line.main_chainage_m[k] + line.main_chainage_m[k + 1]);
      const Eigen::Vector2d a = line.points[k].head<2>(), b = line.points[k + 1].head<2>();
      const bool near = reach_m > 0.0 ? (a.cwiseMax(b).array() >= ctx.lo.array() - reach_m).all() &&
                                            (a.cwiseMin(b).array() < ctx.hi.array() + reach_m).all()
                                      : ctx.owns(mid);
      const bool own = near && xm >= x0 && xm <= x1;
      if (own) {
        if (run.empty())
          run.push_back(frame_point(k));
        run.push_back(frame_point(k + 1));
      } else if (!run.empty()) {
        runs.push_back(std::move(run));
        run.clear();
      }
    }
    if (!run.empty())
      runs.push_back(std::move(run));
  }
  return runs;
}

void extrude(scene::Mesh& mesh, const TileContext& ctx, const std::vector<FramePoint>& run,
             const std::vector<Eigen::Vector2d>& profile, bool closed,
             const std::vector<bool>* level) {
  const std::size_t m = profile.size();
  bool ccw = true;
  if (closed) {
    double area = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      const auto& a = profile[i];
      const auto& b = profile[(i + 1) % m];
      area += a.x() * b.y() - b.x() * a.y();
    }
    ccw = area > 0.0;
  }
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  const Eigen::Vector3d vertical = ctx.up();
  for (const FramePoint& f : run) {
    const Eigen::Vector3d across = vertical.cross(f.tangent).normalized();  // level, + left
    for (std::size_t i = 0; i < m; ++i) {
      const Eigen::Vector2d& p = profile[i];
      mesh.addVertex(ctx.local(level != nullptr && (*level)[i]
                                   ? f.position + p.x() * across + p.y() * vertical
                                   : f.position + p.x() * f.left + p.y() * f.up));
    }
  }
  const std::size_t edges = closed ? m : m - 1;
  const auto um = static_cast<std::uint32_t>(m);
  for (std::uint32_t k = 0; k + 1 < run.size(); ++k)
    for (std::uint32_t i = 0; i < edges; ++i) {
      const std::uint32_t i1 = (i + 1) % um;
      const std::uint32_t a = base + k * um + i, b = base + k * um + i1;
      const std::uint32_t c = base + (k + 1) * um + i1, d = base + (k + 1) * um + i;
      // Outward = edge × tangent for a counter-clockwise profile in (left, up).
      if (ccw)
        mesh.addQuad(a, b, c, d);
      else
        mesh.addQuad(a, d, c, b);
    }
}

Eigen::Vector3d TileContext::ground(const Eigen::Vector3d& p) const {
  return {p.x(), p.y(), env.terrain().heightAt(p.x(), p.y())};
}

std::vector<std::pair<double, double>> mainChainagesNear(const TileContext& ctx, double reach,
                                                         int track) {
  std::vector<std::pair<double, double>> out;
  for (const terrain::Stretch& s : ctx.env.railway().stretchesNear(ctx.lo, ctx.hi, reach))
    if (track < 0 || s.track == track)
      out.emplace_back(s.x0, s.x1);
  std::sort(out.begin(), out.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& r : out)
    if (!merged.empty() && r.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, r.second);
    else
      merged.push_back(r);
  return merged;
}

bool overlaps(const std::vector<std::pair<double, double>>& ranges, double x0, double x1) {
  const auto it = std::upper_bound(ranges.begin(), ranges.end(), x1,
                                   [](double v, const auto& r) { return v < r.first; });
  return it != ranges.begin() && std::prev(it)->second >= x0;
}

std::optional<double> trackOffset(const track::LayoutTrack& t, double x) {
  if (x < t.main_chainage_begin_m || x > t.main_chainage_end_m)
    return std::nullopt;
  if (t.offset.empty())
    return 0.0;  // the main track
  for (const auto& piece : t.offset)
    if (x >= piece.x0 && x <= piece.x1)
      return piece.offset(x);
  return std::nullopt;
}

std::pair<double, double> outermostOver(const track::Layout& layout, double x0, double x1) {
  double left = 0.0, right = 0.0;
  for (double x = x0;; x = std::min(x1, x + 10.0)) {
    const auto [l, r] = outermostOffsets(layout, x);
    left = std::max(left, l);
    right = std::min(right, r);
    if (x >= x1)
      break;
  }
  return {left, right};
}

// Counter-clockwise seen along the track: inside facing out, so callers flip it for a lining.
std::vector<Eigen::Vector2d> horseshoe(double centre, double r, double spring, double floor,
                                       int segments) {
  std::vector<Eigen::Vector2d> out;
  out.emplace_back(centre + r, floor);
  for (int i = 0; i <= segments; ++i) {
    const double a = std::numbers::pi * i / segments;
    out.emplace_back(centre + r * std::cos(a), spring + r * std::sin(a));
  }
  out.emplace_back(centre - r, floor);
  return out;
}

TunnelTube tunnelTube(const track::Layout& layout, const terrain::TerrainParams& T, double x0,
                      double x1) {
  const auto [left, right] = outermostOver(layout, x0, x1);
  const double r = std::max(T.tunnel_half_width_m - 1.0, 0.5 * (left - right) + 3.0);
  return {0.5 * (left + right), r, T.tunnel_crown_m - r};
}

double TunnelTube::roof(double lateral) const {
  // Along the arc's chords, as horseshoe() lays them.
  const auto arc = horseshoe(centre, r, spring, spring, kTunnelArc);
  for (std::size_t i = 1; i + 2 < arc.size(); ++i) {
    const Eigen::Vector2d& a = arc[i + 1];  // the chords run from +r to −r
    const Eigen::Vector2d& b = arc[i];
    if (lateral >= a.x() && lateral <= b.x())
      return a.y() + (lateral - a.x()) / (b.x() - a.x()) * (b.y() - a.y());
  }
  return spring;
}

std::pair<double, double> outermostOffsets(const track::Layout& layout, double x) {
  double left = 0.0, right = 0.0;
  for (const auto& t : layout.tracks)
    if (const std::optional<double> y = trackOffset(t, x)) {
      left = std::max(left, *y);
      right = std::min(right, *y);
    }
  return {left, right};
}

// --- rails, sleepers, ballast ------------------------------------------------------------------

BallastSection ballastSection(const AssetParams& A, double formation) {
  BallastSection b;
  b.sleeper_half = 0.5 * A.sleeper_length_m;
  b.sleeper_top = -kSleeperTopDepth_m;
  b.top = b.sleeper_top - 0.03;  // the crib a little below the sleeper tops
  b.half_top = b.sleeper_half + A.ballast_shoulder_m;
  b.half_bottom = b.half_top + A.ballast_slope * (formation + b.top);
  b.formation = formation;
  return b;
}

std::optional<double> BallastSection::heightAt(double y) const {
  const double a = std::abs(y);
  if (a <= sleeper_half)
    return sleeper_top;
  if (a <= half_top)
    return top;
  if (a < half_bottom)
    return top - (top + formation) * (a - half_top) / (half_bottom - half_top);
  return std::nullopt;
}

void addTrackAssets(TileContext& ctx) {
  const AssetParams& A = ctx.env.params().assets;
  const auto profile = inclinedProfile(A.rail_inclination);
  const double centre = 0.5 * A.gauge_m + gaugeFaceOffset(A.rail_inclination);
  const BallastSection bed_section = ballastSection(A, ctx.env.params().terrain.formation_depth_m);
  const std::vector<Eigen::Vector2d> ballast = {{bed_section.half_bottom, -bed_section.formation},
                                                {bed_section.half_top, bed_section.top},
                                                {-bed_section.half_top, bed_section.top},
                                                {-bed_section.half_bottom, -bed_section.formation}};

  for (const auto& t : ctx.env.railway().layout().tracks) {
    const auto runs = ownedRuns(ctx, t.id, -1e300, 1e300);
    // Sleepers are looked for along every segment reaching into the tile, not only those it
    // owns: a sleeper near the border may lie on a segment the next tile owns (a track along a
    // tile's border may even have no segment here and its sleepers' centres all here).
    const auto sleeper_runs = ownedRuns(ctx, t.id, -1e300, 1e300, 1.0);
    for (const int side : {1, -1}) {
      if (runs.empty())
        break;
      // The rail's section in (left, up): a outward, so left = side · (centre + a).
      std::vector<Eigen::Vector2d> section;
      for (const auto& p : profile)
        section.emplace_back(side * (centre + p.x()), p.y());
      // Every run extruded once, then the quads split into two parts, the running head
      // (near-specular steel) and the web and foot: quad (k, i) of a strip is triangles
      // 2(k·m + i) and +1, and each strip has a whole number of m-quad rings.
      scene::Mesh strip;
      strip.beginPart(scene::cls::kRail, scene::mat::kRailWeb);
      for (const auto& run : runs)
        extrude(strip, ctx, run, section, true);
      const auto& head = rail60E1().head;
      const std::size_t m = section.size();
      auto rail = std::make_shared<scene::Mesh>();
      rail->vertices = std::move(strip.vertices);
      for (const bool head_part : {true, false}) {
        rail->beginPart(scene::cls::kRail,
                        head_part ? scene::mat::kRailHead : scene::mat::kRailWeb);
        for (std::size_t q = 0; q < strip.triangles.size() / 2; ++q)
          if (head[q % m] == head_part)
            for (int h = 0; h < 2; ++h) {
              const auto& tri = strip.triangles[2 * q + h];
              rail->addTriangle(tri[0], tri[1], tri[2]);
            }
      }
      ctx.tile.objects.push_back(scene::Object::place(
          rail, ctx.origin, Eigen::Matrix3f::Identity(),
          scene::trackAssetInstance(t.id, side > 0 ? kRailLeft : kRailRight, 0)));
    }
    auto bed = std::make_shared<scene::Mesh>();
    bed->beginPart(scene::cls::kTrackbed, ctx.env.ballastMaterial());
    // The shoulders' tops tilt with the cant, as the sleepers do; the toes stand on the level
    // formation beside the track (tilted too, on a 105 mm canted curve one floated 0.18 m).
    const std::vector<bool> toes = {true, false, false, true};
    for (const auto& run : runs)
      extrude(*bed, ctx, run, ballast, false, &toes);
    // Sleepers every sleeper_spacing_m of the track's own distance, in the tile holding their
    // centre, square to the track in the plane of the rails.
    bed->beginPart(scene::cls::kSleeper, scene::mat::kConcrete);
    for (const auto& run : sleeper_runs) {
      const double d0 = run.front().distance_m, d1 = run.back().distance_m;
      for (double k = std::ceil(d0 / A.sleeper_spacing_m); k * A.sleeper_spacing_m <= d1;
           k += 1.0) {
        const double d = k * A.sleeper_spacing_m;
        auto it = std::upper_bound(run.begin(), run.end(), d,
                                   [](double v, const FramePoint& f) { return v < f.distance_m; });
        if (it == run.begin())
          it = std::next(it);
        if (it == run.end())
          it = std::prev(it);
        const FramePoint& a = *std::prev(it);
        const FramePoint& b = *it;
        const double w =
            b.distance_m > a.distance_m ? (d - a.distance_m) / (b.distance_m - a.distance_m) : 0.0;
        const track::TrackFrame f = ctx.env.railway().frame(
            t.id, a.main_chainage_m + w * (b.main_chainage_m - a.main_chainage_m));
        const Eigen::Vector3d c =
            f.position + (bed_section.sleeper_top - 0.5 * A.sleeper_height_m) * f.up;
        if (!ctx.owns(c))
          continue;
        scene::addOrientedBox(*bed, ctx.local(c),
                              (0.5 * A.sleeper_width_m * f.tangent).cast<float>(),
                              (0.5 * A.sleeper_length_m * f.left).cast<float>(),
                              (0.5 * A.sleeper_height_m * f.up).cast<float>());
      }
    }
    if (!bed->triangles.empty())
      ctx.tile.objects.push_back(
          scene::Object::place(bed, ctx.origin, Eigen::Matrix3f::Identity(), 0));
  }
}

// --- catenary ----------------------------------------------------------------------------------

namespace {

// Largest |curvature| of the main track over [x0, x1], sampled every 10 m.
double maxCurvature(const track::Track& main, double x0, double x1) {
  double k = 0.0;
  const int n = std::max(2, static_cast<int>(std::ceil((x1 - x0) / 10.0)) + 1);
  for (int i = 0; i < n; ++i) {
    const double x = std::min(main.length(), x0 + (x1 - x0) * i / (n - 1));
    k = std::max(k, std::abs(main.atChainage(x).curvature_1_m));
  }
  return k;
}

}  // namespace

namespace {

// The staggers of `out`'s supports, given each span's mid_offset (the offset of its chord's
// middle from the track, + left): the wire between two supports is the chord, whose offset from
// the track centre is f(τ) = y_a + (y_b − y_a)τ + 4sτ(1 − τ) (s: mid_offset). The staggers y_k
// are chosen among 21 levels in [−a, a] by dynamic programming (Viterbi): every span keeps
// |f| ≤ a everywhere, and among such choices the one closest to the zig-zag (+a, −a, +a, …)
// wins, which in curves puts both ends of a span on the outside.
std::vector<CatenarySupport> chooseStaggers(std::vector<CatenarySupport> out,
                                            const std::vector<double>& mid_offset, double a) {
  const std::size_t n = out.size();
  if (n < 2 || a <= 0.0)
    return out;
  constexpr int kLevels = 21;
  const auto level = [a](int j) { return -a + 2.0 * a * j / (kLevels - 1); };
  // The largest |f| over the span for staggers (ya, yb): at the ends or at the vertex.
  const auto worst = [](double ya, double yb, double s) {
    double m = std::max(std::abs(ya), std::abs(yb));
    if (s != 0.0) {
      const double t = (yb - ya + 4.0 * s) / (8.0 * s);
      if (t > 0.0 && t < 1.0)
        m = std::max(m, std::abs(ya + (yb - ya) * t + 4.0 * s * t * (1.0 - t)));
    }
    return m;
  };
  const auto preferred = [a](std::size_t k) { return k % 2 == 0 ? a : -a; };
  std::vector<std::array<double, kLevels>> cost(n);
  std::vector<std::array<int, kLevels>> from(n);
  for (int j = 0; j < kLevels; ++j)
    cost[0][j] = std::abs(level(j) - preferred(0));
  for (std::size_t k = 0; k + 1 < n; ++k)
    for (int j = 0; j < kLevels; ++j) {
      double best = std::numeric_limits<double>::infinity();
      int arg = 0;
      for (int i = 0; i < kLevels; ++i) {
        // A span beyond the bound costs in proportion to its excess (only if none fits).
        const double excess = std::max(0.0, worst(level(i), level(j), mid_offset[k]) - a - 1e-12);
        const double c = cost[k][i] + 1e6 * excess;
        if (c < best) {
          best = c;
          arg = i;
        }
      }
      cost[k + 1][j] = best + std::abs(level(j) - preferred(k + 1));
      from[k + 1][j] = arg;
    }
  int j = static_cast<int>(std::min_element(cost[n - 1].begin(), cost[n - 1].end()) -
                           cost[n - 1].begin());
  for (std::size_t k = n; k-- > 0;) {
    out[k].stagger_m = level(j);
    if (k > 0)
      j = from[k][j];
  }
  return out;
}

}  // namespace

std::vector<CatenarySupport> planSupports(const terrain::Railway& railway, const AssetParams& A,
                                          int track) {
  const auto& main = railway.main();
  std::vector<CatenarySupport> out;
  // Supports every span along each block, spans shortened in curves so that the track's offset
  // from a span's chord at mid-span, L²κ/8, stays within 1.5 × the stagger (with both ends on
  // the outside the wire then stays within ±stagger).
  const double a = A.stagger_m;
  for (const track::Block& block : railway.route().blocks) {
    const double c0 = block.chainage_begin_m, c1 = block.chainage_end_m;
    const double kappa = maxCurvature(main, c0, c1);
    double span = A.mast_span_m;
    if (kappa > 0.0)
      span = std::min(span, std::sqrt(8.0 * 1.5 * std::max(a, 0.05) / kappa));
    const int n = std::max(1, static_cast<int>(std::ceil((c1 - c0) / span - 1e-9)));
    // The support at a tunnel's exit portal hangs from the crown as the tunnel's others do (a
    // mast there would stand in the portal's ring).
    const bool after_tunnel =
        &block != railway.route().blocks.data() && (&block - 1)->type == track::BlockType::kTunnel;
    for (int k = 0; k < n; ++k)
      out.push_back({c0 + (c1 - c0) * k / n, 0.0,
                     block.type == track::BlockType::kTunnel || (k == 0 && after_tunnel),
                     block.type == track::BlockType::kBridge});
  }
  if (railway.route().blocks.empty())
    return out;
  out.push_back(
      {railway.route().blocks.back().chainage_end_m, 0.0, out.back().tunnel, out.back().bridge});
  const track::LayoutTrack& laid = railway.layout().tracks.at(static_cast<std::size_t>(track));
  const bool auxiliary = laid.kind == track::TrackKind::kAuxiliary;
  if (auxiliary)
    std::erase_if(out, [&](const CatenarySupport& s) {
      return s.x_m <= laid.main_chainage_begin_m || s.x_m >= laid.main_chainage_end_m;
    });
  if (out.size() < 2)
    return auxiliary ? std::vector<CatenarySupport>{} : out;
  // The offset of each span's chord (between the contact points above the track centre) from
  // the track at mid-span, + left.
  std::vector<double> mid_offset(out.size() - 1);
  for (std::size_t k = 0; k + 1 < out.size(); ++k) {
    const track::TrackFrame fa = railway.frame(track, out[k].x_m);
    const track::TrackFrame fb = railway.frame(track, out[k + 1].x_m);
    const track::TrackFrame fm = railway.frame(track, 0.5 * (out[k].x_m + out[k + 1].x_m));
    const Eigen::Vector3d pa = fa.position + A.contact_height_m * fa.up;
    const Eigen::Vector3d pb = fb.position + A.contact_height_m * fb.up;
    const Eigen::Vector3d pm = fm.position + A.contact_height_m * fm.up;
    mid_offset[k] = (0.5 * (pa + pb) - pm).dot(fm.left);
  }
  if (auxiliary) {
    // An auxiliary track's turnouts and curves (R 190 m and more) leave it metres from the chord
    // of a main track's span: its wire hangs over the longest run of spans whose chord keeps
    // within the stagger of the track (its parallel part, where trains stand).
    const double fits = std::max(a, 0.05);
    std::size_t best_begin = 0, best_end = 0;
    for (std::size_t k = 0; k < mid_offset.size();) {
      std::size_t e = k;
      while (e < mid_offset.size() && std::abs(mid_offset[e]) <= fits)
        ++e;
      if (e - k > best_end - best_begin)
        std::tie(best_begin, best_end) = std::pair(k, e);
      k = std::max(e, k + 1);
    }
    if (best_end == best_begin)
      return {};
    const auto at = [](std::size_t i) { return static_cast<std::ptrdiff_t>(i); };
    out =
        std::vector<CatenarySupport>(out.begin() + at(best_begin), out.begin() + at(best_end) + 1);
    mid_offset =
        std::vector<double>(mid_offset.begin() + at(best_begin), mid_offset.begin() + at(best_end));
  }
  return chooseStaggers(std::move(out), mid_offset, a);
}

namespace {

// Between a tunnel's lining and the messenger under it, at least: a margin for the electrical
// clearance to earthed structures [unverified: EN 50119 has the figures; not checked here].
constexpr double kTunnelClearance_m = 0.2;

// Whether another electrified track lies between `track` and its mast at lateral `mast` (from
// the main track) at main chainage x: its wires hang where a cantilever would run.
bool crossesAnotherLine(const Environment& env, const track::LayoutTrack& track, double x,
                        double mast) {
  const std::optional<double> own = trackOffset(track, x);
  if (!own)
    return false;
  for (const track::LayoutTrack& other : env.railway().layout().tracks) {
    if (other.id == track.id)
      continue;
    const auto& supports = env.supports(other.id);
    if (supports.empty() || x < supports.front().x_m || x > supports.back().x_m)
      continue;
    const std::optional<double> y = trackOffset(other, x);
    if (y && (*y - *own) * (*y - mast) < 0.0)
      return true;
  }
  return false;
}

}  // namespace

void addCatenary(TileContext& ctx) {
  const AssetParams& A = ctx.env.params().assets;
  const terrain::Railway& railway = ctx.env.railway();
  const auto& layout = railway.layout();
  const double formation = ctx.env.params().terrain.formation_depth_m;
  // The main-track chainage range near this tile.
  double x_lo = 1e300, x_hi = -1e300;
  for (const auto& s :
       railway.stretchesNear(ctx.lo, ctx.hi, A.mast_offset_m + 20.0 + A.mast_span_m)) {
    x_lo = std::min(x_lo, s.x0);
    x_hi = std::max(x_hi, s.x1);
  }
  const bool has_double =
      layout.tracks.size() > 1 && layout.tracks[1].kind == track::TrackKind::kDouble;
  // The tubes of the tunnels whose supports the tile may hold (its spans reach a span beyond
  // the range), worked out once: each is sampled along its whole length.
  std::vector<std::pair<const terrain::Structure*, TunnelTube>> tubes;
  for (const terrain::Structure& s : railway.structures())
    if (s.type == track::BlockType::kTunnel && s.chainage_end_m >= x_lo - 2.0 * A.mast_span_m &&
        s.chainage_begin_m <= x_hi + 2.0 * A.mast_span_m)
      tubes.emplace_back(
          &s, tunnelTube(layout, ctx.env.params().terrain, s.chainage_begin_m, s.chainage_end_m));
  // The lining's roof over a track at main chainage x in a tunnel, above the top of rail (the
  // crown over the tube's centre, lower off it), and the system height a support keeps under it.
  // (`across`: how far the wire is staggered left of the track.)
  const auto tunnelRoofAt = [&](const track::LayoutTrack& laid, double x, double across) {
    for (const auto& [s, tube] : tubes)
      if (x >= s->chainage_begin_m && x <= s->chainage_end_m)
        return tube.roof(trackOffset(laid, x).value_or(0.0) + across);
    return ctx.env.params().terrain.tunnel_crown_m;
  };
  for (const track::LayoutTrack& laid : layout.tracks) {
    const int track_id = laid.id;
    const auto& supports = ctx.env.supports(track_id);
    const auto systemHeight = [&](const CatenarySupport& s) {
      return s.tunnel ? std::min(A.system_height_m, tunnelRoofAt(laid, s.x_m, s.stagger_m) -
                                                        A.contact_height_m - kTunnelClearance_m)
                      : A.system_height_m;
    };
    // The main track's masts stand on its left, the double track's on its right, beyond the
    // outermost track on that side. An auxiliary track's wires hang from the masts on its side
    // (at the same chainages: its supports are the main track's): only one on the right of a
    // single track has masts of its own.
    const bool auxiliary = laid.kind == track::TrackKind::kAuxiliary;
    const int side = track_id == 0 || (auxiliary && laid.offset_m > 0.0) ? 1 : -1;
    const bool own_masts = !auxiliary || (side < 0 && !has_double);
    const auto first =
        std::lower_bound(supports.begin(), supports.end(), x_lo - A.mast_span_m,
                         [](const CatenarySupport& s, double x) { return s.x_m < x; });
    for (auto it = first;
         it != supports.end() && std::next(it) != supports.end() && it->x_m <= x_hi; ++it) {
      const CatenarySupport& sa = *it;
      const CatenarySupport& sb = *std::next(it);
      const auto index = static_cast<std::int64_t>(it - supports.begin());
      const track::TrackFrame fa = railway.frame(track_id, sa.x_m);
      const track::TrackFrame fb = railway.frame(track_id, sb.x_m);
      const Eigen::Vector3d ra = fa.position + A.contact_height_m * fa.up + sa.stagger_m * fa.left;
      const Eigen::Vector3d rb = fb.position + A.contact_height_m * fb.up + sb.stagger_m * fb.left;
      if (!ctx.owns(ra))
        continue;  // a span belongs to the tile of its first support
      const double system_a = systemHeight(sa), system_b = systemHeight(sb);
      // Mast beside the outermost track on its side, standing vertical. Heights are along the
      // vertical from `base`, the mast's plan position at the track's level.
      const track::TrackFrame fm = railway.frame(0, sa.x_m);
      const auto [left, right] = outermostOffsets(layout, sa.x_m);
      const double lateral = side > 0 ? left + A.mast_offset_m : right - A.mast_offset_m;
      const Eigen::Matrix3d axes = ctx.upright(fm.tangent);
      const Eigen::Vector3d up = axes.col(2);
      const Eigen::Vector3d base = fm.position + lateral * axes.col(1);
      auto mast = std::make_shared<scene::Mesh>();
      mast->beginPart(scene::cls::kPole, scene::mat::kGalvanisedSteel);
      if (!sa.tunnel) {
        const double top = ctx.heightOver(fa.position, base) + A.mast_height_m;
        const double wire = ctx.heightOver(ra, base);  // the contact wire at the support
        const double foot =
            (sa.bridge ? -formation
                       : std::min(-formation, ctx.heightOver(ctx.ground(base), base))) -
            0.3;
        if (own_masts)  // else only the arms, from the mast already standing there
          scene::addOrientedBox(
              *mast, ctx.local(base + 0.5 * (foot + top) * up), (0.15 * axes.col(0)).cast<float>(),
              (0.15 * axes.col(1)).cast<float>(), (0.5 * (top - foot) * up).cast<float>());
        const double support = wire + A.system_height_m;
        if (!crossesAnotherLine(ctx.env, laid, sa.x_m, lateral)) {
          // Cantilever (messenger support) and registration arm out to the contact wire.
          scene::addCylinder(*mast, ctx.local(base + support * up),
                             ctx.local(ra + A.system_height_m * up), 0.04f, 0.04f, 6);
          scene::addCylinder(*mast, ctx.local(base + (wire - 0.4) * up), ctx.local(ra), 0.03f,
                             0.03f, 6);
        } else {
          // Another track's wires hang between the mast and this track: a cantilever would run
          // through them. A boom instead, half a metre over every messenger (the mast raised to
          // carry it), with a drop tube a metre short of the wire carrying the messenger's
          // support and the registration arm (as a twin-track cantilever's).
          const double boom = support + 0.5;
          if (own_masts && top < boom + 0.3)
            scene::addOrientedBox(*mast, ctx.local(base + (0.5 * (top + boom) + 0.15) * up),
                                  (0.15 * axes.col(0)).cast<float>(),
                                  (0.15 * axes.col(1)).cast<float>(),
                                  (0.5 * (boom + 0.3 - top) * up).cast<float>());
          const Eigen::Vector3d toward = (base - ra) - (base - ra).dot(up) * up;  // level
          const Eigen::Vector3d drop = ra + toward.normalized();
          scene::addCylinder(*mast, ctx.local(base + boom * up),
                             ctx.local(drop + (boom - wire) * up), 0.05f, 0.05f, 6);
          scene::addCylinder(*mast, ctx.local(drop + (boom - wire) * up),
                             ctx.local(drop - 0.4 * up), 0.04f, 0.04f, 6);
          scene::addCylinder(*mast, ctx.local(drop + A.system_height_m * up),
                             ctx.local(ra + A.system_height_m * up), 0.03f, 0.03f, 6);
          scene::addCylinder(*mast, ctx.local(drop - 0.4 * up), ctx.local(ra), 0.03f, 0.03f, 6);
        }
      } else {
        // In tunnels the supports hang from the lining's roof.
        const double roof =
            ctx.heightOver(fa.position, ra) + tunnelRoofAt(laid, sa.x_m, sa.stagger_m);
        scene::addCylinder(*mast, ctx.local(ra + system_a * up), ctx.local(ra + roof * up), 0.04f,
                           0.04f, 6);
      }
      ctx.tile.objects.push_back(
          scene::Object::place(mast, ctx.origin, Eigen::Matrix3f::Identity(),
                               scene::trackAssetInstance(track_id, kMast, index)));
      // Contact wire (straight between registrations), messenger (a parabola from the supports
      // down to sag at mid-span) and vertical droppers between them.
      const double sag = std::min(0.6, std::min(system_a, system_b) - 0.5);
      const int drops =
          std::max(1, static_cast<int>(std::ceil((rb - ra).norm() / A.dropper_spacing_m)));
      scene::Wire contact{{ctx.local(ra), ctx.local(rb)},
                          0.006f,
                          scene::cls::kWire,
                          scene::mat::kCopper,
                          scene::trackAssetInstance(track_id, kContactWire, index)};
      scene::Wire messenger{{},
                            0.0055f,
                            scene::cls::kWire,
                            scene::mat::kCopper,
                            scene::trackAssetInstance(track_id, kMessenger, index)};
      for (int j = 0; j <= drops; ++j) {
        const double tau = static_cast<double>(j) / drops;
        const Eigen::Vector3d on_contact = ra + tau * (rb - ra);
        const Eigen::Vector3d on_messenger =
            on_contact +
            ((system_a == system_b ? system_a : (1.0 - tau) * system_a + tau * system_b) -
             4.0 * sag * tau * (1.0 - tau)) *
                ctx.up();
        messenger.points.push_back(ctx.local(on_messenger));
        if (j > 0 && j < drops)
          ctx.tile.wires.push_back({{ctx.local(on_contact), ctx.local(on_messenger)},
                                    0.0025f,
                                    scene::cls::kWire,
                                    scene::mat::kCopper,
                                    scene::trackAssetInstance(track_id, kDropper, index * 64 + j)});
      }
      ctx.tile.wires.push_back(std::move(contact));
      ctx.tile.wires.push_back(std::move(messenger));
    }
  }
}

}  // namespace detail
}  // namespace trainsim::environment
