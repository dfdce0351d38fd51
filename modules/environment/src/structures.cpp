// Platforms, tunnels, bridges, fences and signals along the main track; obstacles placed by
// hand.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "assets.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/random.hpp"

namespace trainsim::environment::detail {
namespace {

// A platform shorter than this is not laid (m).
constexpr double kShortestPlatform_m = 20.0;

// The outermost offsets over a chainage range of the tracks where they run parallel to the main
// track: an auxiliary track's legs, which turn in from a turnout or a dead end, left out.
std::pair<double, double> parallelOffsetsOver(const track::Layout& layout, double x0, double x1) {
  double left = 0.0, right = 0.0;
  for (const auto& t : layout.tracks)
    for (const auto& piece : t.offset)
      if (piece.shape == track::OffsetPiece::Shape::kLine && piece.y0 == piece.y1 &&
          piece.x1 > x0 && piece.x0 < x1) {
        left = std::max(left, piece.y0);
        right = std::min(right, piece.y0);
      }
  return {left, right};
}

// The longest stretch of [x0, x1] (sampled every metre) where no track lies further out on
// `side` (+1 left, −1 right) than `edge`: where a platform along `edge` leaves every track's
// legs clear. Empty (first > second) where there is none.
std::pair<double, double> clearStretch(const track::Layout& layout, double x0, double x1, int side,
                                       double edge) {
  std::pair<double, double> best{1.0, 0.0}, run{1.0, 0.0};
  const int n = std::max(1, static_cast<int>(std::ceil(x1 - x0)));
  for (int i = 0; i <= n; ++i) {
    const double x = x0 + (x1 - x0) * i / n;
    const auto [l, r] = outermostOffsets(layout, x);
    if (side > 0 ? l <= edge + 1e-6 : r >= edge - 1e-6) {
      run = run.first > run.second ? std::pair{x, x} : std::pair{run.first, x};
      if (run.second - run.first > best.second - best.first)
        best = run;
    } else {
      run = {1.0, 0.0};
    }
  }
  return best;
}

}  // namespace

std::optional<PlatformSpan> platformSpan(const track::Layout& layout, const AssetParams& A,
                                         const terrain::Structure& station, int side) {
  // Beyond the outermost track on the side where the tracks run parallel. An auxiliary track's
  // leg turning in within the station would stand in the platform: the platform keeps to the
  // longest stretch clear of it (standing beyond the leg instead put it metres from every
  // track).
  const auto [par_left, par_right] =
      parallelOffsetsOver(layout, station.chainage_begin_m, station.chainage_end_m);
  const double outermost = side > 0 ? par_left : par_right;
  const auto [x0, x1] =
      clearStretch(layout, station.chainage_begin_m, station.chainage_end_m, side, outermost);
  if (x1 - x0 < kShortestPlatform_m)
    return std::nullopt;
  const double edge = outermost + side * A.platform_edge_m;
  return PlatformSpan{x0, x1, edge, edge + side * A.platform_width_m};
}

BridgeDeck bridgeDeck(const track::Layout& layout, const AssetParams& A,
                      const terrain::Structure& bridge) {
  const auto [left, right] = outermostOver(layout, bridge.chainage_begin_m, bridge.chainage_end_m);
  // 3 m beyond the outermost tracks, or wide enough to carry the catenary's masts.
  const double half = A.catenary ? std::max(3.0, A.mast_offset_m + 0.5) : 3.0;
  return {right - half, left + half};
}

void addStructures(TileContext& ctx) {
  const AssetParams& A = ctx.env.params().assets;
  const terrain::TerrainParams& T = ctx.env.params().terrain;
  const terrain::Railway& railway = ctx.env.railway();
  const auto& layout = railway.layout();
  const double formation = T.formation_depth_m;
  // The main track's chainages near the tile (ownedRuns' own margin): a structure outside them
  // has nothing in the tile, and is passed over without asking the track.
  const std::vector<std::pair<double, double>> near = mainChainagesNear(ctx, 10.0, 0);
  for (const terrain::Structure& s : railway.structures()) {
    if (!overlaps(near, s.chainage_begin_m, s.chainage_end_m))
      continue;
    const auto runs = ownedRuns(ctx, 0, s.chainage_begin_m, s.chainage_end_m);
    if (runs.empty())
      continue;
    auto mesh = std::make_shared<scene::Mesh>();
    int kind = kTunnel;
    if (s.type == track::BlockType::kStation) {
      // Side platforms (platformSpan()) level with platform_height_m above the top of rail,
      // their fronts down to the formation. Each platform is an object of its own (an instance
      // each for panoptic labels).
      for (const int side : {1, -1}) {
        auto platform = std::make_shared<scene::Mesh>();
        platform->beginPart(scene::cls::kPlatform, scene::mat::kConcrete);
        if (const std::optional<PlatformSpan> p = platformSpan(layout, A, s, side)) {
          const std::vector<Eigen::Vector2d> box = {{p->edge, -formation},
                                                    {p->edge, A.platform_height_m},
                                                    {p->back, A.platform_height_m},
                                                    {p->back, -formation}};
          for (const auto& run : ownedRuns(ctx, 0, p->x0, p->x1))
            extrude(*platform, ctx, run, box, true);
        }
        if (!platform->triangles.empty())
          ctx.tile.objects.push_back(scene::Object::place(
              platform, ctx.origin, Eigen::Matrix3f::Identity(),
              scene::trackAssetInstance(0, side > 0 ? kPlatformLeft : kPlatformRight, s.block_id)));
      }
    } else if (s.type == track::BlockType::kTunnel) {
      // One tube around all tracks, crown tunnel_crown_m above the rails, lining facing in.
      mesh->beginPart(scene::cls::kTunnel, scene::mat::kConcrete);
      const auto [centre, r, spring] = tunnelTube(layout, T, s.chainage_begin_m, s.chainage_end_m);
      auto lining = horseshoe(centre, r, spring, -formation, kTunnelArc);
      std::reverse(lining.begin(), lining.end());  // clockwise: normals face the inside
      lining.push_back(lining.front());            // and the invert, the floor under the track bed
      for (const auto& run : runs) {
        // extrude() orients closed profiles outward; the lining is open, so the order decides.
        extrude(*mesh, ctx, run, lining, false);
      }
      // Behind each portal the ground is cut away over the bore, within tunnel_half_width_m of
      // the tracks and a cell more, wider than the tube: a shell as wide as the portal's ring
      // covers the tube there, so that no line of sight from above passes between the tube and
      // the cut ground (the sky showed through). 20 m in: the cut ends within about 11 m.
      const double cover = std::min(20.0, 0.5 * (s.chainage_end_m - s.chainage_begin_m));
      const auto shell = horseshoe(centre, r + 4.5, spring, -formation - 3.0, kTunnelArc);
      for (const auto& [x0, x1] : {std::pair(s.chainage_begin_m, s.chainage_begin_m + cover),
                                   std::pair(s.chainage_end_m - cover, s.chainage_end_m)})
        for (const auto& run : ownedRuns(ctx, 0, x0, x1))
          extrude(*mesh, ctx, run, shell, false);  // counter-clockwise: facing out
      // Portal rings at the ends this tile owns: between the lining and a larger horseshoe.
      for (const double x : {s.chainage_begin_m, s.chainage_end_m}) {
        const track::TrackFrame f = railway.frame(0, x);
        if (!ctx.owns(f.position))
          continue;
        const auto inner = horseshoe(centre, r, spring, -formation, kTunnelArc);
        // The terrain is cut away in the cells around the bore (within tunnel_half_width_m of a
        // track, and a cell more): the ring is wide enough to close that cut at the portal, on
        // the far side of a tube offset to the middle of several tracks too, and reaches 3 m
        // into the ground.
        const auto outer = horseshoe(centre, r + 4.5, spring, -formation - 3.0, kTunnelArc);
        const double facing = x == s.chainage_begin_m ? -1.0 : 1.0;  // out of the tunnel
        // Quad a b c d as laid out for the portal at the tunnel's end; flipped at its beginning.
        const auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
          if (facing > 0)
            mesh->addQuad(a, b, c, d);
          else
            mesh->addQuad(a, d, c, b);
        };
        const auto base = static_cast<std::uint32_t>(mesh->vertices.size());
        for (std::size_t i = 0; i < inner.size(); ++i) {
          mesh->addVertex(ctx.local(f.position + inner[i].x() * f.left + inner[i].y() * f.up));
          mesh->addVertex(ctx.local(f.position + outer[i].x() * f.left + outer[i].y() * f.up));
        }
        for (std::uint32_t i = 0; i + 1 < inner.size(); ++i) {
          quad(base + 2 * i, base + 2 * i + 1, base + 2 * i + 3, base + 2 * i + 2);
        }
        // And a sill under the opening, 3 m into the ground, for the same cut in front of it.
        const auto sill = static_cast<std::uint32_t>(mesh->vertices.size());
        for (const double u : {centre - r, centre + r})
          for (const double v : {-formation, -formation - 3.0})
            mesh->addVertex(ctx.local(f.position + u * f.left + v * f.up));
        quad(sill, sill + 1, sill + 3, sill + 2);
        // And an apron over the cut cells in front of the portal, 2 cm above the formation (no
        // coincident faces with the ground), seen from outside and through the opening.
        const auto apron = static_cast<std::uint32_t>(mesh->vertices.size());
        for (const double u : {centre - r - 4.5, centre + r + 4.5})
          for (const double w : {0.0, 1.5})
            mesh->addVertex(ctx.local(f.position + u * f.left + facing * w * f.tangent +
                                      (0.02 - formation) * f.up));
        quad(apron, apron + 1, apron + 3, apron + 2);  // facing up
      }
    } else if (s.type == track::BlockType::kBridge) {
      // Deck under the ballast of all tracks, parapets on both edges, piers down to the valley.
      kind = kBridge;
      mesh->beginPart(scene::cls::kBridge, scene::mat::kConcrete);
      const BridgeDeck d = bridgeDeck(layout, A, s);
      const double l = d.left, rr = d.right, deck = 1.5;
      const std::vector<Eigen::Vector2d> slab = {
          {l, -formation - deck}, {l, -formation}, {rr, -formation}, {rr, -formation - deck}};
      const std::vector<Eigen::Vector2d> parapet_l = {
          {l, -formation}, {l, 1.0}, {l - kParapet_m, 1.0}, {l - kParapet_m, -formation}};
      const std::vector<Eigen::Vector2d> parapet_r = {
          {rr + kParapet_m, -formation}, {rr + kParapet_m, 1.0}, {rr, 1.0}, {rr, -formation}};
      for (const auto& run : runs) {
        extrude(*mesh, ctx, run, slab, true);
        extrude(*mesh, ctx, run, parapet_l, true);
        extrude(*mesh, ctx, run, parapet_r, true);
      }
      const double length = s.chainage_end_m - s.chainage_begin_m;
      // Spans of at most bridge_pier_spacing_m between the abutments.
      const int spans = std::max(1, static_cast<int>(std::ceil(length / A.bridge_pier_spacing_m)));
      for (int p = 1; p < spans; ++p) {
        const double x = s.chainage_begin_m + length * p / spans;
        const track::TrackFrame f = railway.frame(0, x);
        const Eigen::Vector3d top =
            f.position + 0.5 * (l + rr) * f.left - (formation + deck) * f.up;
        if (!ctx.owns(top))
          continue;
        const double height = T.valley_depth_m + 3.0;
        const Eigen::Matrix3d axes = ctx.upright(f.tangent);
        scene::addOrientedBox(*mesh, ctx.local(top - 0.5 * height * axes.col(2)),
                              axes.col(0).cast<float>(),
                              (0.35 * (l - rr) * axes.col(1)).cast<float>(),
                              (0.5 * height * axes.col(2)).cast<float>());
      }
    }
    if (!mesh->triangles.empty())
      ctx.tile.objects.push_back(
          scene::Object::place(mesh, ctx.origin, Eigen::Matrix3f::Identity(),
                               scene::trackAssetInstance(0, kind, s.block_id)));
  }
}

void addFencesAndSignals(TileContext& ctx) {
  const AssetParams& A = ctx.env.params().assets;
  const terrain::Railway& railway = ctx.env.railway();
  const auto& layout = railway.layout();
  const auto& blocks = railway.route().blocks;
  const RandomStream fences(ctx.env.seed(), "assets/fence");
  const double formation = ctx.env.params().terrain.formation_depth_m;
  // A fence post or a signal stands its offset beyond the outermost track at its chainage, so
  // only the chainages where some track passes within that of the tile can hold one of the
  // tile's: the rest of the route is not walked (a tile costs the same on a 1000 km route as on
  // a 1 km one). 5 m spare covers the polyline's chords and the cant.
  const std::vector<std::pair<double, double>> near =
      mainChainagesNear(ctx, std::max(A.fence_offset_m, A.signal_offset_m) + 5.0);
  const auto inNear = [&](double x) { return overlaps(near, x, x); };
  const auto overlapsNear = [&](double x0, double x1) { return overlaps(near, x0, x1); };
  for (const track::Block& b : blocks) {
    if (b.type != track::BlockType::kStraight && b.type != track::BlockType::kCurve)
      continue;
    if (!overlapsNear(b.chainage_begin_m, b.chainage_end_m))
      continue;
    // Fences: per block and side with fence_probability, posts every 2.5 m and two strands.
    for (const int side : {1, -1}) {
      const double u = fences.uniform4(static_cast<std::uint64_t>(b.id), side > 0 ? 0 : 1)[0];
      if (u > A.fence_probability)
        continue;
      auto posts = std::make_shared<scene::Mesh>();
      posts->beginPart(scene::cls::kFence, scene::mat::kGalvanisedSteel);
      const auto instance = scene::trackAssetInstance(0, kFence, b.id * 2 + (side > 0 ? 0 : 1));
      std::vector<Eigen::Vector3d> strand;
      const auto flush = [&] {
        for (const double h : {0.5, 1.2})
          if (strand.size() > 1) {
            scene::Wire w{{}, 0.002f, scene::cls::kFence, scene::mat::kGalvanisedSteel, instance};
            for (const auto& p : strand)
              w.points.push_back(ctx.local(p + h * ctx.up()));
            ctx.tile.wires.push_back(std::move(w));
          }
        strand.clear();
      };
      for (double x = b.chainage_begin_m + 1.25; x < b.chainage_end_m; x += 2.5) {
        if (!inNear(x) && strand.empty())
          continue;
        const auto [l, r] = outermostOffsets(layout, x);
        const double lateral = side > 0 ? l + A.fence_offset_m : r - A.fence_offset_m;
        const track::TrackFrame f = railway.frame(0, x);
        const Eigen::Matrix3d axes = ctx.upright(f.tangent);
        const Eigen::Vector3d p = ctx.ground(f.position + lateral * axes.col(1));
        if (!ctx.owns(p)) {
          // The bay from this tile's last post to the next belongs to this tile, as a span to
          // its first support's.
          if (!strand.empty())
            strand.push_back(p);
          flush();
          continue;
        }
        // From 0.3 m in the ground to 1.4 m above it.
        scene::addOrientedBox(
            *posts, ctx.local(p + 0.55 * axes.col(2)), (0.04 * axes.col(0)).cast<float>(),
            (0.04 * axes.col(1)).cast<float>(), (0.85 * axes.col(2)).cast<float>());
        strand.push_back(p);
      }
      flush();
      if (!posts->triangles.empty())
        ctx.tile.objects.push_back(
            scene::Object::place(posts, ctx.origin, Eigen::Matrix3f::Identity(), instance));
    }
  }
  // Signals at every boundary between main blocks, 20 m before it for the trains they govern.
  // Lines run on the left: the main track's stand on its left and face the train as it comes.
  // The double track is signalled both ways, its signals on its right: for its own direction
  // (the trains running against the main chainage) 20 m past the boundary, so the train sees
  // their backs, and for wrong-line running in the train's direction 20 m before it, facing the
  // train. A signal's index is its block's id, plus kSignalAgainst for one of the other way.
  const bool has_double =
      layout.tracks.size() > 1 && layout.tracks[1].kind == track::TrackKind::kDouble;
  struct Placing {
    int track_id;
    bool against;  // governs the trains running against the main chainage
  };
  for (std::size_t i = 1; i < blocks.size(); ++i) {
    for (const auto [track_id, against] :
         {Placing{0, false}, Placing{1, false}, Placing{1, true}}) {
      if (track_id == 1 && !has_double)
        continue;
      const double x = blocks[i].chainage_begin_m + (against ? 20.0 : -20.0);
      if (x < 0.0 || x > blocks.back().chainage_end_m || !inNear(x))
        continue;
      const auto [l, r] = outermostOffsets(layout, x);
      const track::TrackFrame f = railway.frame(0, x);
      const Eigen::Matrix3d along = ctx.upright(f.tangent);
      const double lateral = track_id == 0 ? l + A.signal_offset_m : r - A.signal_offset_m;
      const Eigen::Vector3d p = f.position + lateral * along.col(1) - formation * along.col(2);
      if (!ctx.owns(p))
        continue;
      // The head's face is its −x side: x runs the way the trains it governs go.
      const Eigen::Matrix3d axes = against ? ctx.upright(-f.tangent) : along;
      const scene::InstanceId instance = scene::trackAssetInstance(
          track_id, kSignal, blocks[i].id + (against ? kSignalAgainst : 0));
      ctx.tile.objects.push_back(
          scene::Object::place(ctx.env.signalPrototype(*ctx.env.signalAspect(instance)), p,
                               axes.cast<float>(), instance));
    }
  }
}

void addObstacles(TileContext& ctx) {
  const std::vector<Obstacle>& list = ctx.env.params().objects.obstacles;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::optional<PlacedObstacle>& p = ctx.env.obstacle(i);
    if (!p || !ctx.owns(p->foot))
      continue;
    // Upright along the local vertical, facing heading_deg from its track's direction.
    const Eigen::Matrix3d axes =
        ctx.upright(p->along) *
        Eigen::AngleAxisd(list[i].heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    ctx.tile.objects.push_back(scene::Object::place(ctx.env.obstaclePrototype(list[i].kind),
                                                    p->foot, axes.cast<float>(), p->instance));
  }
}

}  // namespace trainsim::environment::detail

namespace trainsim::environment {

std::optional<PlacedObstacle> Environment::placeObstacle(std::size_t i) const {
  if (obstacleLeftOut(railway_->layout(), railway_->route().blocks, params_.terrain,
                      params_.objects.obstacles.at(i)))
    return std::nullopt;
  Obstacle o = params_.objects.obstacles.at(i);
  const track::LayoutTrack& on = railway_->layout().tracks[static_cast<std::size_t>(o.track)];
  o.chainage_m = std::clamp(o.chainage_m, on.main_chainage_begin_m, on.main_chainage_end_m);
  PlacedObstacle out;
  out.instance =
      scene::trackAssetInstance(o.track, detail::kObstacle, static_cast<std::int64_t>(i));
  out.along = railway_->frame(o.track, o.chainage_m).tangent;
  out.foot = surfaceUnder(o.track, o.chainage_m, o.offset_m);
  // The surface under its footprint's corners (along its track and across it; a curve's
  // bending over a few metres is left out).
  for (const Eigen::Vector2d& k : obstacleCorners(o)) {
    const double x =
        std::clamp(o.chainage_m + k.x(), on.main_chainage_begin_m, on.main_chainage_end_m);
    const double dz = surfaceUnder(o.track, x, o.offset_m + k.y()).z() - out.foot.z();
    out.above_m = std::max(out.above_m, dz);
    out.below_m = std::min(out.below_m, dz);
  }
  constexpr double kUneven_m = 0.2;
  if (out.above_m > kUneven_m || out.below_m < -kUneven_m)
    logWarn(fmt::format(
        "objects.obstacles[{}]: the surface under its footprint lies {:.2f} m above to {:.2f} m "
        "below its foot (it stands across the edge of a ballast bed, a platform, a parapet or a "
        "bridge's deck): parts of it sink into the step or overhang it; move it clear of the "
        "edge",
        i, out.above_m, -out.below_m));
  return out;
}

Eigen::Vector3d Environment::surfaceUnder(int track, double chainage_m, double offset_m) const {
  const track::TrackFrame f = railway_->frame(track, chainage_m);
  const Eigen::Vector3d over = f.position + offset_m * f.left;
  // On the highest track bed or structure under it (a bed in its track's canted axes); beyond
  // them on the terrain, or in a tunnel, where the terrain is the hill above, on the formation.
  const detail::BallastSection bed =
      detail::ballastSection(params_.assets, params_.terrain.formation_depth_m);
  std::optional<Eigen::Vector3d> on_bed;
  for (const track::LayoutTrack& t : railway_->layout().tracks) {
    if (!(chainage_m >= t.main_chainage_begin_m && chainage_m <= t.main_chainage_end_m))
      continue;
    const track::TrackFrame g = t.id == track ? f : railway_->frame(t.id, chainage_m);
    const double y = (over - g.position).dot(g.left);
    if (const std::optional<double> h = bed.heightAt(y)) {
      const Eigen::Vector3d surface = g.position + y * g.left + *h * g.up;
      if (!on_bed || surface.z() > on_bed->z())
        on_bed = surface;
    }
  }
  // Or on a structure's top: a station's platform, a bridge's deck or parapet (in the main
  // track's axes, as they are built).
  const track::TrackFrame main = track == 0 ? f : railway_->frame(0, chainage_m);
  const double y = (over - main.position).dot(main.left);
  const auto onStructure = [&](double height) {
    const Eigen::Vector3d surface = main.position + y * main.left + height * main.up;
    if (!on_bed || surface.z() > on_bed->z())
      on_bed = surface;
  };
  for (const terrain::Structure& s : railway_->structures()) {
    if (!(chainage_m >= s.chainage_begin_m && chainage_m <= s.chainage_end_m))
      continue;
    if (s.type == track::BlockType::kStation) {
      for (const int side : {1, -1}) {
        const std::optional<detail::PlatformSpan> p =
            detail::platformSpan(railway_->layout(), params_.assets, s, side);
        if (p && chainage_m >= p->x0 && chainage_m <= p->x1 && y >= std::min(p->edge, p->back) &&
            y <= std::max(p->edge, p->back))
          onStructure(params_.assets.platform_height_m);
      }
    } else if (s.type == track::BlockType::kBridge) {
      const detail::BridgeDeck d = detail::bridgeDeck(railway_->layout(), params_.assets, s);
      if (y >= d.right && y <= d.left) {
        const bool parapet = y < d.right + detail::kParapet_m || y > d.left - detail::kParapet_m;
        onStructure(parapet ? 1.0 : -bed.formation);
      }
    }
  }
  if (on_bed)
    return *on_bed;
  const bool tunnel = std::ranges::any_of(railway_->route().blocks, [&](const track::Block& b) {
    return b.type == track::BlockType::kTunnel && chainage_m >= b.chainage_begin_m &&
           chainage_m <= b.chainage_end_m;
  });
  if (tunnel)
    return over - bed.formation * f.up;
  return {over.x(), over.y(), terrain_.heightAt(over.x(), over.y())};
}

}  // namespace trainsim::environment
