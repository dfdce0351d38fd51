// Catenary, tunnels, bridges and signals over a whole generated route: the contact wire against
// the track frames, masts out of tunnels and their portals, booms over another track's wires,
// the messenger under a tunnel's lining, the cut ground under the tube's shell, bridge decks and
// piers, each signal's lit aspect and the way it faces (the track bed, fences, platforms, the
// clearance of masts and signals, and objects: environment_assets_test.cpp; the obstacles a
// scenario places: environment_obstacles_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "unit/environment_world.hpp"

namespace trainsim {
namespace {

using scenario::Json;

TEST(Assets, NoMastStandsInATunnelOrItsPortal) {
  // Within a tunnel and at its portals the supports hang from the crown: a mast at the exit
  // portal stood through the portal's ring (the first open-line support was placed there).
  const World& w = defaultWorld();
  const auto along = alongTheMainTrack(w);
  std::vector<std::pair<double, double>> tunnels;
  for (const terrain::Structure& b : w.railway().structures())
    if (b.type == track::BlockType::kTunnel)
      tunnels.emplace_back(b.chainage_begin_m, b.chainage_end_m);
  ASSERT_EQ(tunnels.size(), 2u);
  int masts = 0, near_portals = 0;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      const auto asset = scene::trackAsset(o.instance);
      if (!asset || asset->kind != 3 || o.mesh->vertices.size() < 24)
        continue;
      // A mast's box is its first 24 vertices, from under the formation to 8 m up (an arm or a
      // hanger reaches 2 m at most).
      double low = 1e300, high = -1e300;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (std::uint32_t v = 0; v < 24; ++v) {
        low = std::min(low, o.worldVertex(v).z());
        high = std::max(high, o.worldVertex(v).z());
        c += o.worldVertex(v) / 24.0;
      }
      if (high - low < 6.0)
        continue;
      ++masts;
      const double x = along(c)[0];
      for (const auto& [begin, end] : tunnels) {
        EXPECT_FALSE(x > begin - 0.5 && x < end + 0.5)
            << "a mast at " << x << " m, tunnel " << begin << " ... " << end << " m";
        near_portals += std::abs(x - end) < 70.0;
      }
    }
  EXPECT_GT(masts, 100);
  EXPECT_GT(near_portals, 0);
}

TEST(Assets, ABridgesDeckCarriesItsMastsAndItsPiersCarryEverySpan) {
  // On the default route's 244 m bridge: every mast standing on it lies within the deck's width
  // (they stood beside it, their feet in the air), and the piers leave no span longer than
  // bridge_pier_spacing_m (a 50 m bridge had none, a longer one spans up to twice that).
  const World& w = defaultWorld();
  const environment::AssetParams& A = w.env().params().assets;
  const double formation = w.env().params().terrain.formation_depth_m;
  const auto along = alongTheMainTrack(w);
  int bridges = 0;
  for (const terrain::Structure& b : w.railway().structures()) {
    if (b.type != track::BlockType::kBridge)
      continue;
    ++bridges;
    double deck_left = -1e9, deck_right = 1e9;
    std::vector<double> piers;  // the chainages of the piers' vertices
    std::vector<std::array<double, 3>> masts;
    for (const auto& tile : allTiles())
      for (const auto& o : tile->objects) {
        const auto asset = scene::trackAsset(o.instance);
        if (!asset)
          continue;
        if (asset->kind == 10 && asset->index == b.block_id)
          for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
            const auto [x, lateral, up] = along(o.worldVertex(v));
            if (up > -formation - 1.6)  // the deck and parapets
              std::tie(deck_left, deck_right) =
                  std::pair(std::max(deck_left, lateral), std::min(deck_right, lateral));
            else
              piers.push_back(x);
          }
        if (asset->kind == 3 && o.mesh->vertices.size() > 24)  // a mast's box (8 corners x 3)
          for (std::uint32_t v = 0; v < 24; ++v)
            if (const auto p = along(o.worldVertex(v));
                p[0] > b.chainage_begin_m + 1.0 && p[0] < b.chainage_end_m - 1.0)
              masts.push_back(p);
      }
    ASSERT_FALSE(masts.empty());
    for (const auto& [x, lateral, up] : masts) {
      EXPECT_LT(lateral, deck_left) << "a mast beside the deck at " << x << " m";
      EXPECT_GT(lateral, deck_right) << "a mast beside the deck at " << x << " m";
    }
    // The piers' centres: their vertices in runs along the track (a pier is 2 m thick).
    std::sort(piers.begin(), piers.end());
    std::vector<double> centres;
    for (std::size_t i = 0, j = 0; i < piers.size(); i = j) {
      for (j = i; j < piers.size() && piers[j] - piers[i] < 3.0; ++j) {
      }
      centres.push_back(0.5 * (piers[i] + piers[j - 1]));
    }
    centres.push_back(b.chainage_end_m);
    double previous = b.chainage_begin_m;
    for (const double x : centres) {  // 0.1 m: chainage from the plan's chords
      EXPECT_LE(x - previous, A.bridge_pier_spacing_m + 0.1) << "a span ending at " << x << " m";
      previous = x;
    }
  }
  EXPECT_GT(bridges, 0);
}

// The least distance between segments ab and cd (clamped closest points, Ericson 5.1.9).
double segmentDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = b - a, v = d - c, w = a - c;
  const double uu = u.dot(u), vv = v.dot(v), uv = u.dot(v), uw = u.dot(w), vw = v.dot(w);
  const double den = uu * vv - uv * uv;
  double s = den > 1e-12 ? std::clamp((uv * vw - vv * uw) / den, 0.0, 1.0) : 0.0;
  double t = (uv * s + vw) / vv;
  if (t < 0.0 || t > 1.0) {
    t = std::clamp(t, 0.0, 1.0);
    s = std::clamp((uv * t - uw) / uu, 0.0, 1.0);
  }
  return (a + s * u - c - t * v).norm();
}

TEST(Assets, NoTracksCatenarySupportRunsThroughAnotherTracksWires) {
  // Where an auxiliary track lies between a track and its mast, the track's cantilever ran
  // through the other's wires (0.21 m under its contact wire, through its messenger); a boom over
  // them carries it instead. Every arm, boom and drop tube of a track's supports keeps 0.3 m
  // from every other track's contact wire and messenger.
  std::vector<std::pair<int, std::array<Eigen::Vector3d, 2>>> arms, wires;  // track, segment
  for (const auto& tile : allTiles()) {
    for (const auto& o : tile->objects) {
      const auto asset = scene::trackAsset(o.instance);
      if (!asset || asset->kind != 3)
        continue;
      // Boxes of 24 vertices (the mast, and a raised mast's extension) and cylinders of 14: six
      // rim pairs (bottom, top) and the axis' ends, every bottom rim vertex within its radius of
      // the bottom end (which no six vertices of a box are).
      const auto& m = o.mesh->vertices;
      std::uint32_t v = 0;
      while (v + 14 <= m.size()) {
        bool cylinder = true;
        for (std::uint32_t k = 0; k < 6; ++k)
          cylinder = cylinder && (m[v + 2 * k] - m[v + 12]).norm() < 0.06f &&
                     (m[v + 2 * k + 1] - m[v + 13]).norm() < 0.06f;
        if (!cylinder) {
          v += 24;
          continue;
        }
        arms.push_back({asset->track_id, {o.worldVertex(v + 12), o.worldVertex(v + 13)}});
        v += 14;
      }
    }
    for (const auto& wire : tile->wires) {
      const auto asset = scene::trackAsset(wire.instance);
      if (!asset || (asset->kind != 4 && asset->kind != 5))
        continue;
      for (std::size_t k = 0; k + 1 < wire.points.size(); ++k)
        wires.push_back({asset->track_id,
                         {tile->origin + wire.points[k].cast<double>(),
                          tile->origin + wire.points[k + 1].cast<double>()}});
    }
  }
  ASSERT_GT(arms.size(), 200u);
  PlanGrid grid;  // the wires' segments by their first points
  for (std::size_t i = 0; i < wires.size(); ++i)
    grid.add(wires[i].second[0], i);
  std::size_t near_another = 0;
  for (const auto& [track, arm] : arms)
    grid.near(arm[0], 4, [&, &track = track, &arm = arm](std::size_t i) {
      if (wires[i].first == track)
        return;
      const double d = segmentDistance(arm[0], arm[1], wires[i].second[0], wires[i].second[1]);
      near_another += d < 2.0;
      EXPECT_GE(d, 0.3) << "track " << track << "'s support at " << arm[0].transpose()
                        << " and track " << wires[i].first << "'s wire";
    });
  EXPECT_GT(near_another, 10u);  // the booms over the auxiliary tracks' wires
}

TEST(Assets, InATunnelAsLowAsValidateAllowsTheMessengerKeepsUnderTheLining) {
  // With terrain.tunnel_crown_m 7.1 m, the least validate accepts, the lining's roof over the
  // double track's two tracks (off the tube's centre) is 6.78 m above the rails: the messenger,
  // 1.6 m over the 5.3 m contact wire, ran through it. In a tunnel the system height is cut to
  // keep it 0.2 m under the roof, read here off the lining's own mesh.
  const World w = makeWorld(Json::parse(R"({"terrain": {"tunnel_crown_m": 7.1}})"));
  const auto along = alongTheMainTrack(w);
  std::set<scene::TileIndex> near;
  for (const Segment& s : allSegments(w))
    if (s.type == track::LayoutBlockType::kTunnel)
      near.insert(w.env().grid().tileAt(s.a.x(), s.a.y()));
  std::vector<std::array<double, 3>> lining, messenger;  // (chainage, lateral, up)
  for (const scene::TileIndex& i : near) {
    const auto tile = w.env().tile(i);
    for (const auto& o : tile->objects)
      if (const auto asset = scene::trackAsset(o.instance); asset && asset->kind == 9)
        for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v)
          lining.push_back(along(o.worldVertex(v)));
    for (const auto& wire : tile->wires)
      if (const auto asset = scene::trackAsset(wire.instance); asset && asset->kind == 5)
        for (const auto& p : wire.points)
          messenger.push_back(along(tile->origin + p.cast<double>()));
  }
  std::size_t inside = 0;
  double least = 1e300;
  for (const auto& [x, lateral, up] : messenger) {
    // The roof over the point: between the lining's nearest vertices either side of it, across
    // the rings within a metre along the track (the tube's arc, above the point).
    double below = -1e300, above = 1e300, z_below = 0.0, z_above = 0.0;
    for (const auto& [lx, ll, lu] : lining) {
      if (std::abs(lx - x) > 1.0 || lu < up - 1.0)
        continue;
      if (ll <= lateral && ll > below)
        std::tie(below, z_below) = std::pair(ll, lu);
      if (ll >= lateral && ll < above)
        std::tie(above, z_above) = std::pair(ll, lu);
    }
    if (below < -1e299 || above > 1e299)
      continue;  // not under a lining (outside the tunnels)
    const double roof = above > below
                            ? z_below + (lateral - below) / (above - below) * (z_above - z_below)
                            : z_below;
    least = std::min(least, roof - up);
    ++inside;
  }
  EXPECT_GT(inside, 50u);
  EXPECT_GE(least, 0.19) << "a messenger " << least << " m under the tunnel's roof";
}

TEST(Assets, TheGroundCutOverATunnelsFirstMetresLiesUnderItsShell) {
  // Behind a portal the ground is cut away over the bore (the terrain's `bore` vertices), wider
  // than the tube's lining: a line of sight from above passed between the two, and the sky
  // showed through the hill. A shell as wide as the portal's ring covers the first 20 m. Every
  // cut vertex lies laterally within the tunnel's mesh inside the tube (the ring, its sill and
  // apron left out) and within 20 m of a portal.
  const World& w = defaultWorld();
  const auto along = alongTheMainTrack(w);
  std::set<scene::TileIndex> near;
  for (const Segment& s : allSegments(w))
    if (s.type == track::LayoutBlockType::kTunnel)
      near.insert(w.env().grid().tileAt(s.a.x(), s.a.y()));
  std::vector<std::pair<double, double>> portals;
  for (const terrain::Structure& b : w.railway().structures())
    if (b.type == track::BlockType::kTunnel)
      portals.emplace_back(b.chainage_begin_m, b.chainage_end_m);
  const auto portalOf = [&](double x) {
    for (std::size_t k = 0; k < portals.size(); ++k)
      for (const double p : {portals[k].first, portals[k].second})
        if (std::abs(x - p) < 20.5)
          return static_cast<int>(2 * k + (p == portals[k].second ? 1 : 0));
    return -1;
  };
  std::map<int, std::pair<double, double>> extent;  // per portal: the mesh's laterals behind it
  std::vector<std::array<double, 3>> cut;
  for (const scene::TileIndex& i : near) {
    const auto tile = w.env().tile(i);
    for (const auto& o : tile->objects)
      if (const auto asset = scene::trackAsset(o.instance); asset && asset->kind == 9)
        for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
          const auto [x, lateral, up] = along(o.worldVertex(v));
          // Inside the tube, half a metre and more behind the portal (the ring, its sill and the
          // apron in front of it left out).
          const int p = portalOf(x);
          if (p < 0 || x < portals[p / 2].first + 0.5 || x > portals[p / 2].second - 0.5)
            continue;
          auto& [lo, hi] = extent.try_emplace(p, 1e300, -1e300).first->second;
          lo = std::min(lo, lateral);
          hi = std::max(hi, lateral);
        }
    const terrain::TerrainTile t = w.env().terrain().sceneTile(i);
    for (int r = 0; r < t.n; ++r)
      for (int c = 0; c < t.n; ++c)
        if (t.inBore(c, r))
          cut.push_back(along(t.vertex(c, r)));
  }
  ASSERT_GT(cut.size(), 50u);
  for (const auto& [x, lateral, up] : cut) {
    const int p = portalOf(x);
    ASSERT_GE(p, 0) << "ground cut at " << x << " m, more than 20 m from a portal";
    ASSERT_TRUE(extent.count(p));
    // A cell with a corner in the bore is cut: the cell's width beyond the vertex, covered too.
    const double cell = w.env().params().terrain.spacing_m;
    EXPECT_GT(lateral - cell, extent[p].first) << "ground cut beside the tube at " << x << " m";
    EXPECT_LT(lateral + cell, extent[p].second) << "ground cut beside the tube at " << x << " m";
  }
}

TEST(Assets, ContactWiresHangAtTheContactHeightWithinTheStagger) {
  const World& w = defaultWorld();
  const environment::AssetParams& A = w.env().params().assets;
  std::vector<track::Polyline> lines;
  for (const track::LayoutTrack& t : w.railway().layout().tracks)
    lines.push_back(track::samplePolyline(w.railway().main(), t));
  int spans = 0;
  std::map<int, int> spans_of;  // by track
  for (const auto& tile : allTiles())
    for (const auto& wire : tile->wires) {
      if (((wire.instance >> 36) & 0xFF) != 4)
        continue;  // contact wires
      ++spans;
      const int track_id = static_cast<int>((wire.instance >> 44) & 0xFFF);
      ++spans_of[track_id];
      for (int s = 0; s <= 8; ++s) {
        const Eigen::Vector3d p =
            tile->origin +
            (wire.points.front() + (wire.points.back() - wire.points.front()) * (s / 8.0f))
                .cast<double>();
        const auto& line = lines[track_id];
        std::size_t best = 0;
        for (std::size_t k = 0; k < line.points.size(); ++k)
          if ((line.points[k] - p).head<2>().squaredNorm() <
              (line.points[best] - p).head<2>().squaredNorm())
            best = k;
        // The frame at the foot of the perpendicular, by bisection on the chainage.
        double lo = line.main_chainage_m[best > 0 ? best - 1 : 0];
        double hi = line.main_chainage_m[std::min(best + 1, line.points.size() - 1)];
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          const track::TrackFrame f = w.railway().frame(track_id, mid);
          ((p - f.position).dot(f.tangent) > 0 ? lo : hi) = mid;
        }
        const track::TrackFrame f = w.railway().frame(track_id, 0.5 * (lo + hi));
        const Eigen::Vector3d r = p - f.position;
        EXPECT_LE(std::abs(r.dot(f.left)), A.stagger_m + 0.01)
            << "track " << track_id << " span " << (wire.instance & 0xFFFFFFFFFull) << " at " << s
            << "/8, chainage " << 0.5 * (lo + hi);
        EXPECT_NEAR(r.dot(f.up), A.contact_height_m, 0.05);
      }
    }
  EXPECT_GT(spans, 150);
  // The auxiliary tracks too are electrified, over their parallel part (at least 300 m, so five
  // spans and more of 60 m), from the main track's supports that lie along it.
  for (const track::LayoutTrack& t : w.railway().layout().tracks)
    if (t.kind == track::TrackKind::kAuxiliary) {
      EXPECT_GE(spans_of[t.id], 4) << "track " << t.id;
      EXPECT_GE(w.env().supports(t.id).size(), 5u) << "track " << t.id;
      for (const environment::CatenarySupport& s : w.env().supports(t.id))
        EXPECT_TRUE(
            std::ranges::any_of(w.env().supports(0), [&](const auto& m) { return m.x_m == s.x_m; }))
            << "track " << t.id << " support at " << s.x_m << " m has no mast";
    }
  // Continuous from span to span over the whole route, tile borders included: each span starts
  // where the one before it ends.
  std::map<std::pair<int, std::int64_t>, std::pair<Eigen::Vector3d, Eigen::Vector3d>> ends;
  for (const auto& tile : allTiles())
    for (const auto& wire : tile->wires)
      if (((wire.instance >> 36) & 0xFF) == 4)
        ends[{static_cast<int>((wire.instance >> 44) & 0xFFF),
              static_cast<std::int64_t>(wire.instance & 0xFFFFFFFFFull)}] = {
            tile->origin + wire.points.front().cast<double>(),
            tile->origin + wire.points.back().cast<double>()};
  int joints = 0;
  for (auto it = ends.begin(); std::next(it) != ends.end(); ++it) {
    const auto next = std::next(it);
    if (next->first.first != it->first.first || next->first.second != it->first.second + 1)
      continue;
    EXPECT_LT((it->second.second - next->second.first).norm(), 1e-3);
    ++joints;
  }
  EXPECT_GT(joints, 150);
}

TEST(Signals, ShowOneLitAspectThatTheTrainsOwnTrackNeverSetsAtStop) {
  // Each aspect's prototype lights its own lamp (an emitting material) and no other.
  const World& w = defaultWorld();
  const environment::Environment& env = w.env();
  const std::pair<environment::SignalAspect, scene::MaterialId> lit[] = {
      {environment::SignalAspect::kStop, scene::mat::kSignalLampRed},
      {environment::SignalAspect::kCaution, scene::mat::kSignalLampYellow},
      {environment::SignalAspect::kProceed, scene::mat::kSignalLampGreen}};
  for (const auto& [aspect, lamp] : lit) {
    std::vector<scene::MaterialId> emitting;
    for (const scene::MeshPart& part : env.signalPrototype(aspect)->parts)
      if (scene::material(part.material).emits())
        emitting.push_back(part.material);
    EXPECT_EQ(emitting, std::vector<scene::MaterialId>{lamp})
        << environment::signalAspectName(aspect);
  }

  // Every signal in the scene is drawn with its own aspect's prototype, and other things have
  // none.
  std::set<scene::InstanceId> signals;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      const auto aspect = env.signalAspect(o.instance);
      const auto asset = scene::trackAsset(o.instance);
      ASSERT_EQ(aspect.has_value(), asset && asset->kind == 12);
      if (!aspect)
        continue;
      EXPECT_EQ(o.mesh, env.signalPrototype(*aspect));
      signals.insert(o.instance);
    }
  EXPECT_GE(signals.size(), 20u);  // 14 block starts on the main track and on the double track

  // The shares over many signals (instance ids as the layout makes them) follow signal_caution
  // and signal_stop, and track 0 (the train's) never shows stop; the same id always draws the
  // same aspect, in another environment of the same seed too.
  const Json shares = {{"assets", {{"signal_caution", 0.25}, {"signal_stop", 0.4}}}};
  const World again = makeWorld(shares), twin = makeWorld(shares);
  constexpr int kSignals = 20000;
  for (const int track : {0, 1}) {
    std::map<environment::SignalAspect, int> count;
    for (int i = 0; i < kSignals; ++i) {
      const scene::InstanceId id = scene::trackAssetInstance(track, 12, i);
      const auto aspect = again.env().signalAspect(id);
      ASSERT_TRUE(aspect.has_value());
      ++count[*aspect];
      ASSERT_EQ(aspect, twin.env().signalAspect(id));
    }
    const double stop = track == 0 ? 0.0 : 0.4;
    const auto share = [&](environment::SignalAspect a) {
      return static_cast<double>(count[a]) / kSignals;
    };
    EXPECT_EQ(count[environment::SignalAspect::kStop] == 0, track == 0);
    // Binomial σ at n = 20 000 is at most 0.0035: 4σ.
    EXPECT_NEAR(share(environment::SignalAspect::kStop), stop, 0.014) << track;
    EXPECT_NEAR(share(environment::SignalAspect::kCaution), 0.25, 0.014) << track;
    EXPECT_NEAR(share(environment::SignalAspect::kProceed), 1.0 - 0.25 - stop, 0.014) << track;
  }
}

TEST(Signals, EachSignalFacesTheTrainsItGoverns) {
  // Left-hand running: the main track's signals stand on its left 20 m before each boundary
  // between blocks, their lamps facing the train as it comes. The double track is signalled
  // both ways on its right: its own direction's signals (index + 2^32) govern the trains running
  // against the main chainage, so they stand 20 m past the boundary and the train sees their
  // backs; its wrong-line signals stand 20 m before it and face the train.
  const World& w = defaultWorld();
  const auto along = alongTheMainTrack(w);
  const auto& blocks = w.railway().route().blocks;
  std::map<std::pair<int, bool>, int> seen;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      const auto asset = scene::trackAsset(o.instance);
      if (!asset || asset->kind != 12)
        continue;
      const bool against = asset->index >= (std::int64_t{1} << 32);
      const auto [x, lateral, up] = along(o.position);
      const Eigen::Vector3d tangent = w.railway().frame(0, x).tangent;
      // The head's lamps are on its −x side (the prototype's face): x runs the way its trains go.
      const double facing = o.linear.col(0).cast<double>().normalized().dot(tangent);
      double boundary = std::numeric_limits<double>::infinity();
      for (std::size_t i = 1; i < blocks.size(); ++i)
        if (std::abs(blocks[i].chainage_begin_m - x) < std::abs(boundary - x))
          boundary = blocks[i].chainage_begin_m;
      if (against) {
        EXPECT_LT(facing, -0.99) << x;
        EXPECT_NEAR(x, boundary + 20.0, 0.5);
      } else {
        EXPECT_GT(facing, 0.99) << x;
        EXPECT_NEAR(x, boundary - 20.0, 0.5);
      }
      EXPECT_EQ(lateral > 0.0, asset->track_id == 0) << x;
      ++seen[{asset->track_id, against}];
    }
  EXPECT_GE((seen[{0, false}]), 10);
  EXPECT_EQ((seen[{0, true}]), 0);
  EXPECT_GE((seen[{1, false}]), 10);
  EXPECT_GE((seen[{1, true}]), 10);
}

}  // namespace
}  // namespace trainsim
