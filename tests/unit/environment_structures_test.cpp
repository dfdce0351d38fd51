// Catenary, tunnels, bridges and signals over a whole generated route: the contact wire against
// the track frames, masts out of tunnels and their portals, booms over another track's wires,
// the messenger under a tunnel's lining, the cut ground under the tube's shell, bridge decks and
// piers, each signal's lit aspect and the way it faces (the track bed, fences, platforms, the
// clearance of masts and signals, and objects: environment_assets_test.cpp), and the obstacles
// a scenario places.
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

TEST(Obstacles, StandWhereTheScenarioPutsThemAsObjectsOfTheirOwn) {
  // A person on the main track's sleepers, a car across the double track, a cow in the field:
  // each one object of its kind's class, on its track (instances.csv's track), its feet on the
  // sleepers' tops or on the ground, facing the way heading_deg says, in one tile only.
  Json patch;
  patch["objects"]["obstacles"] = Json::array(
      {{{"kind", "person"}, {"chainage_m", 300.0}, {"offset_m", 0.2}, {"heading_deg", 180.0}},
       {{"kind", "car"}, {"track", 1}, {"chainage_m", 700.0}, {"offset_m", 0.0}},
       {{"kind", "cow"}, {"chainage_m", 900.0}, {"offset_m", 7.0}, {"heading_deg", 45.0}},
       {{"kind", "car"}, {"track", 9}, {"chainage_m", 300.0}},
       {{"kind", "car"}, {"chainage_m", 9000.0}}});
  const World w = makeWorld(patch);
  const std::vector<environment::Obstacle>& list = w.env().params().objects.obstacles;
  ASSERT_EQ(list.size(), 5u);
  // The last two cannot stand where they are put (no track 9; the route is 6 km): left out.
  EXPECT_EQ(environment::obstacleOffTheLayout(w.railway().layout(), list[3]),
            "the layout has no track 9 (it has 3: railroad.json lists them, 0 the main track)");
  EXPECT_EQ(environment::obstacleOffTheLayout(w.railway().layout(), list[4]),
            "9000 m is not on track 0, which runs from main chainage 0.0 to 6000.0 m");
  const scene::ClassId classes[] = {scene::cls::kPerson, scene::cls::kCar, scene::cls::kAnimal};
  const double heights[] = {1.75, 1.45, 1.42};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_FALSE(environment::obstacleOffTheLayout(w.railway().layout(), list[i])) << i;
    const environment::Obstacle& ob = list[i];
    const track::TrackFrame f = w.railway().frame(ob.track, ob.chainage_m);
    const Eigen::Vector3d over = f.position + ob.offset_m * f.left;
    // The tiles around it: the object is in exactly one of them.
    std::vector<const scene::Object*> found;
    std::vector<std::shared_ptr<const scene::Tile>> tiles;
    const scene::TileGrid grid = w.env().grid();
    const scene::TileIndex at = grid.tileAt(over.x(), over.y());
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        if (w.env().tiles().contains({at.i + di, at.j + dj}))
          tiles.push_back(w.env().tile({at.i + di, at.j + dj}));
    for (const auto& tile : tiles)
      for (const scene::Object& o : tile->objects) {
        const auto asset = scene::trackAsset(o.instance);
        EXPECT_FALSE(asset && asset->kind == 13 && asset->index >= 3);
        if (asset && asset->kind == 13 && asset->index == static_cast<std::int64_t>(i))
          found.push_back(&o);
      }
    ASSERT_EQ(found.size(), 1u) << i;
    const scene::Object& o = *found.front();
    EXPECT_EQ(w.env().trackOf(o.instance), ob.track);
    for (const scene::MeshPart& part : o.mesh->parts)
      EXPECT_EQ(part.cls, classes[i]) << i;
    // Feet: on the sleepers' tops (182 mm under the top of rail) on the track, on the ground
    // off it; as tall as its kind along the local vertical.
    double low = 1e300, high = -1e300;
    const Eigen::Vector3d up = o.linear.col(2).cast<double>();
    for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
      low = std::min(low, (o.worldVertex(v) - over).dot(up));
      high = std::max(high, (o.worldVertex(v) - over).dot(up));
    }
    const double foot = std::abs(ob.offset_m) <= 1.3
                            ? -0.182 * f.up.dot(up)
                            : w.env().terrain().heightAt(over.x(), over.y()) - over.z();
    EXPECT_NEAR(low, foot, 0.01) << i;
    EXPECT_NEAR(high - low, heights[i], 0.01) << i;
    // Its kind's footprint (which the train's stop short of it reads) is the mesh's plan bounds.
    Eigen::AlignedBox2d plan;
    for (const Eigen::Vector3f& v : o.mesh->vertices)
      plan.extend(v.head<2>().cast<double>());
    const Eigen::AlignedBox2d footprint = environment::obstacleFootprint(ob.kind);
    EXPECT_LT((plan.min() - footprint.min()).cwiseAbs().maxCoeff(), 0.01) << i;
    EXPECT_LT((plan.max() - footprint.max()).cwiseAbs().maxCoeff(), 0.01) << i;
    // Facing: the object's x is the track's direction turned by heading_deg about the vertical.
    const Eigen::Vector3d forward = o.linear.col(0).cast<double>();
    const Eigen::Vector3d t = (f.tangent - f.tangent.dot(up) * up).normalized();
    const double heading = std::atan2(up.dot(t.cross(forward)), t.dot(forward));
    EXPECT_NEAR(heading, std::remainder(ob.heading_rad, 2.0 * M_PI), 1e-5) << i;
  }
}

// The tiles of `w`'s scene around xy (its own and the eight about it).
std::vector<std::shared_ptr<const scene::Tile>> tilesAround(const World& w,
                                                            const Eigen::Vector2d& xy) {
  std::vector<std::shared_ptr<const scene::Tile>> out;
  const scene::TileIndex at = w.env().grid().tileAt(xy.x(), xy.y());
  for (int di = -1; di <= 1; ++di)
    for (int dj = -1; dj <= 1; ++dj)
      if (w.env().tiles().contains({at.i + di, at.j + dj}))
        out.push_back(w.env().tile({at.i + di, at.j + dj}));
  return out;
}

// The highest surface of `tiles` of the given classes under xy: its height, interpolated in the
// triangle's plan, and its class (none where no triangle is under xy).
std::optional<std::pair<double, scene::ClassId>> highestUnder(
    const std::vector<std::shared_ptr<const scene::Tile>>& tiles, const Eigen::Vector2d& xy,
    const std::vector<scene::ClassId>& classes) {
  std::optional<std::pair<double, scene::ClassId>> out;
  for (const auto& tile : tiles)
    for (const scene::Object& o : tile->objects)
      for (const scene::MeshPart& part : o.mesh->parts) {
        if (std::ranges::find(classes, part.cls) == classes.end())
          continue;
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             ++t) {
          const auto& tri = o.mesh->triangles[t];
          const Eigen::Vector3d a = o.worldVertex(tri[0]), b = o.worldVertex(tri[1]),
                                c = o.worldVertex(tri[2]);
          // Barycentric coordinates of xy in the triangle's plan.
          const Eigen::Vector2d e1 = (b - a).head<2>(), e2 = (c - a).head<2>();
          const double det = e1.x() * e2.y() - e1.y() * e2.x();
          if (std::abs(det) < 1e-12)
            continue;
          const Eigen::Vector2d d = xy - a.head<2>();
          const double u = (d.x() * e2.y() - d.y() * e2.x()) / det;
          const double v = (e1.x() * d.y() - e1.y() * d.x()) / det;
          if (u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9)
            continue;
          const double z = a.z() + u * (b - a).z() + v * (c - a).z();
          if (!out || z > out->first)
            out = std::pair{z, part.cls};
        }
      }
  return out;
}

TEST(Obstacles, StandOnTheSurfaceTheSensorsSeeUnderThem) {
  // Persons beside the main track: on the ballast's top past the sleepers' ends, on its shoulder
  // slope, between the double track's two beds, past the beds on the ground; on a station's
  // platform and on a bridge's deck beside the ballast. Each foot is checked against the scene's
  // own meshes (the highest ballast, sleeper, terrain, platform or bridge triangle under it,
  // interpolated), not against the placement's own section.
  const std::vector<scene::ClassId> ground = {scene::cls::kTrackbed, scene::cls::kSleeper,
                                              scene::cls::kTerrain, scene::cls::kPlatform,
                                              scene::cls::kBridge};
  // Where the platform and the deck are, found in the default scene: across the middle of the
  // station and of the bridge, the first offset (every 10 cm out from the main track, on the
  // side with the platform, and on the right for the deck) where the highest surface is the
  // structure's, then 1.5 m (the platform) or 0.3 m (the deck) further out.
  const World& plain = defaultWorld();
  const auto found = [&](track::BlockType type, double side, scene::ClassId cls, double in) {
    for (const terrain::Structure& s : plain.railway().structures()) {
      if (s.type != type)
        continue;
      const double x = 0.5 * (s.chainage_begin_m + s.chainage_end_m);
      const track::TrackFrame f = plain.railway().frame(0, x);
      const auto tiles = tilesAround(plain, f.position.head<2>());
      for (double y = 0.0; y < 20.0; y += 0.1) {
        const auto top = highestUnder(tiles, (f.position + side * y * f.left).head<2>(), ground);
        if (top && top->second == cls)
          return std::pair{x, side * (y + in)};
      }
    }
    ADD_FAILURE() << "no structure of that kind found";
    return std::pair{0.0, 0.0};
  };
  std::pair<double, double> platform =
      found(track::BlockType::kStation, 1.0, scene::cls::kPlatform, 1.5);
  if (platform.second == 0.0)
    return;
  const std::pair<double, double> deck =
      found(track::BlockType::kBridge, -1.0, scene::cls::kBridge, 0.3);
  Json patch;
  patch["objects"]["obstacles"] =
      Json::array({{{"chainage_m", 1300.0}, {"offset_m", 1.5}},
                   {{"chainage_m", 1350.0}, {"offset_m", 2.2}},
                   {{"chainage_m", 1400.0}, {"offset_m", -2.0}},
                   {{"chainage_m", 1450.0}, {"offset_m", 3.5}},
                   {{"chainage_m", platform.first}, {"offset_m", platform.second}},
                   {{"chainage_m", deck.first}, {"offset_m", deck.second}},
                   {{"kind", "car"},
                    {"chainage_m", deck.first + 10.0},
                    {"offset_m", deck.second},
                    {"heading_deg", 0.0}}});
  const World w = makeWorld(patch);
  for (std::size_t i = 0; i < 6; ++i) {
    const std::optional<environment::PlacedObstacle>& p = w.env().obstacle(i);
    ASSERT_TRUE(p) << i;
    const auto surface = highestUnder(tilesAround(w, p->foot.head<2>()), p->foot.head<2>(), ground);
    ASSERT_TRUE(surface) << i;
    // The ballast and the structures within 2 cm; the terrain within 5 cm (its mesh is
    // simplified to 2 cm of the height grid, whose own triangles differ from the grid's
    // bilinear heights by a little more).
    EXPECT_NEAR(p->foot.z(), surface->first, i == 3 ? 0.05 : 0.02) << i;
  }
  for (const auto& [i, cls] :
       {std::pair{4, scene::cls::kPlatform}, std::pair{5, scene::cls::kBridge}}) {
    const Eigen::Vector2d xy = w.env().obstacle(static_cast<std::size_t>(i))->foot.head<2>();
    EXPECT_EQ(highestUnder(tilesAround(w, xy), xy, ground)->second, cls) << i;
  }
  // The first three stand on ballast, above the formation the terrain meets beside the bed; the
  // person on the platform platform_height_m above the top of rail, the one on the bridge at
  // the formation, metres above the valley floor under the deck.
  const double rail = w.railway().frame(0, 1300.0).position.z();
  EXPECT_NEAR(w.env().obstacle(0)->foot.z(), rail - 0.212, 0.01);
  const environment::AssetParams& A = w.env().params().assets;
  EXPECT_NEAR(w.env().obstacle(4)->foot.z(),
              w.railway().frame(0, platform.first).position.z() + A.platform_height_m, 0.05);
  const Eigen::Vector3d on_deck = w.env().obstacle(5)->foot;
  EXPECT_GT(on_deck.z() - w.env().terrain().heightAt(on_deck.x(), on_deck.y()), 3.0);
  // Level under their whole footprint but the two on the beds' slopes (the person's 0.24 m
  // across them) and the car on the deck, whose 1.8 m width reaches the ballast bed on one side
  // and past the deck's edge on the other: said in above_m and below_m (and warned of).
  for (const std::size_t i : {0u, 4u, 5u}) {
    EXPECT_LT(w.env().obstacle(i)->above_m, 0.02) << i;
    EXPECT_GT(w.env().obstacle(i)->below_m, -0.02) << i;
  }
  for (const std::size_t i : {1u, 2u})
    EXPECT_LT(w.env().obstacle(i)->above_m - w.env().obstacle(i)->below_m, 0.2) << i;
  EXPECT_GT(w.env().obstacle(6)->above_m, 0.2);
  EXPECT_LT(w.env().obstacle(6)->below_m, -3.0);
}

TEST(Obstacles, InATunnelOnlyWithinItsBore) {
  // The default route's first tunnel: the bore's walls found in the scene's own lining (its
  // vertices below 1 m above the rails across the tunnel's middle), and persons facing across
  // the track (their footprint ±0.12 m across it) 0.2 m inside and outside them. One outside
  // would stand in the rock of the hill: left out, saying why. And the route's end chainage is
  // on the route, though the layout's sum of lengths may fall a hair short of it.
  const World& w = defaultWorld();
  const terrain::TerrainParams& terrain = w.env().params().terrain;
  const std::vector<track::Block>& blocks = w.railway().route().blocks;
  const auto tunnel = std::ranges::find_if(
      blocks, [](const track::Block& b) { return b.type == track::BlockType::kTunnel; });
  ASSERT_NE(tunnel, blocks.end());
  const double x = 0.5 * (tunnel->chainage_begin_m + tunnel->chainage_end_m);
  const track::TrackFrame f = w.railway().frame(0, x);
  double left = -1e300, right = 1e300;
  for (const auto& tile : tilesAround(w, f.position.head<2>()))
    for (const scene::Object& o : tile->objects)
      for (const scene::MeshPart& part : o.mesh->parts) {
        if (part.cls != scene::cls::kTunnel)
          continue;
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             ++t)
          for (const std::uint32_t v : o.mesh->triangles[t]) {
            const Eigen::Vector3d p = o.worldVertex(v) - f.position;
            if (std::abs(p.dot(f.tangent)) < 5.0 && p.dot(f.up) < 1.0) {
              left = std::max(left, p.dot(f.left));
              right = std::min(right, p.dot(f.left));
            }
          }
      }
  ASSERT_GT(left, 2.0);
  ASSERT_LT(right, -2.0);
  const auto person = [&](double offset) {
    environment::Obstacle o;
    o.chainage_m = x;
    o.offset_m = offset;
    return o;
  };
  const auto leftOut = [&](const environment::Obstacle& o) {
    return environment::obstacleLeftOut(w.railway().layout(), blocks, terrain, o);
  };
  EXPECT_FALSE(leftOut(person(left - 0.32))) << left;
  EXPECT_FALSE(leftOut(person(right + 0.32))) << right;
  for (const double offset : {left - 0.08, left + 5.0, right + 0.08}) {
    const auto why = leftOut(person(offset));
    ASSERT_TRUE(why) << offset;
    EXPECT_NE(why->find("it would stand in the rock"), std::string::npos) << *why;
  }
  // A car along the track fits where one across it does not (4.4 m long, 1.8 m wide).
  environment::Obstacle car = person(left - 1.2);
  car.kind = environment::ObstacleKind::kCar;
  car.heading_rad = 0.0;
  EXPECT_FALSE(leftOut(car));
  car.heading_rad = std::numbers::pi / 2;
  EXPECT_TRUE(leftOut(car));
  // As far out before the tunnel, in the open, and at the route's end.
  environment::Obstacle open = person(left + 5.0);
  open.chainage_m = tunnel->chainage_begin_m - 30.0;
  EXPECT_FALSE(leftOut(open));
  environment::Obstacle end = person(3.0);
  end.chainage_m = std::round(w.railway().layout().tracks[0].main_chainage_end_m);
  EXPECT_FALSE(leftOut(end)) << end.chainage_m;
}

}  // namespace
}  // namespace trainsim
