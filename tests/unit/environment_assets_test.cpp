// Track assets and trackside objects over a whole generated route: the rail gauge and cant
// measured on the meshes, sleepers, ballast and fences across tile borders, clearance of masts,
// signals and fences, what stands upright along the local vertical, platforms, object footprints
// checked pairwise and against every track, their feet, placement order (catenary, tunnels,
// bridges and the signals' aspects and facing: environment_structures_test.cpp).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>

#include <Eigen/Eigenvalues>

#include "unit/environment_world.hpp"

namespace trainsim {
namespace {

using scenario::Json;

TEST(Assets, RailsSitAtGaugeAndFollowTheCant) {
  const World& w = defaultWorld();
  const auto& profile = environment::rail60E1().points;
  const std::size_t m = profile.size();
  // The inner corner of the head at 14 mm below the top, before inclination: index of (−36, −14).
  std::size_t corner = m;
  for (std::size_t i = 0; i < m; ++i)
    if (std::abs(profile[i].x() + 0.036) < 1e-9 && std::abs(profile[i].y() + 0.014) < 1e-9)
      corner = i;
  ASSERT_LT(corner, m);
  const track::Polyline main =
      track::samplePolyline(w.railway().main(), w.railway().layout().tracks[0]);
  int checked = 0, canted = 0;
  for (const auto& tile : allTiles()) {
    const scene::Object* left = nullptr;
    const scene::Object* right = nullptr;
    for (const auto& o : tile->objects) {
      if (o.instance == scene::trackAssetInstance(0, 1, 0))
        left = &o;
      if (o.instance == scene::trackAssetInstance(0, 2, 0))
        right = &o;
    }
    if (!left || !right)
      continue;
    // Both meshes hold the same rings (one per polyline point) in the same order.
    ASSERT_EQ(left->mesh->vertices.size(), right->mesh->vertices.size());
    for (std::size_t ring = 0; ring * m < left->mesh->vertices.size(); ring += 7) {
      const Eigen::Vector3d a = left->worldVertex(static_cast<std::uint32_t>(ring * m + corner));
      const Eigen::Vector3d b = right->worldVertex(static_cast<std::uint32_t>(ring * m + corner));
      // The inclination moves the corner by (1 − cos β)·36 mm and lifts it < 1 mm: the gauge
      // between the two corners is 1435 mm within 0.5 mm.
      EXPECT_NEAR((a - b).norm(), 1.435, 5e-4);
      // Cant: the line between the rails is tilted by the track's roll at that point.
      const Eigen::Vector3d mid = 0.5 * (a + b);
      std::size_t best = 0;
      for (std::size_t k = 0; k < main.points.size(); ++k)
        if ((main.points[k] - mid).head<2>().squaredNorm() <
            (main.points[best] - mid).head<2>().squaredNorm())
          best = k;
      const track::TrackFrame f = w.railway().frame(0, main.main_chainage_m[best]);
      const double tilt = std::asin((a.z() - b.z()) / (a - b).norm());
      EXPECT_NEAR(tilt, f.roll_rad, 2e-3) << "at chainage " << main.main_chainage_m[best];
      if (std::abs(f.roll_rad) > 0.02)
        ++canted;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(canted, 10);
  EXPECT_NEAR(environment::gaugeFaceOffset(1.0 / 40.0), 0.036, 1e-3);
}

TEST(Assets, EveryTrackHasASleeperEverySpacingAcrossEveryTileBorder) {
  // Every sleeper_spacing_m of each track's own distance there is one sleeper, whichever tile
  // it falls in: a sleeper near a tile's border may lie on a polyline segment the next tile
  // owns (they went missing there, 1-2 at every border).
  const World& w = defaultWorld();
  const double spacing = w.env().params().assets.sleeper_spacing_m;
  // The sleepers' centres in plan, hashed by 1 m cells.
  std::map<std::pair<long, long>, std::vector<Eigen::Vector2d>> centres;
  std::size_t sleepers = 0;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects)
      for (const scene::MeshPart& part : o.mesh->parts) {
        if (part.cls != scene::cls::kSleeper)
          continue;
        ASSERT_EQ(part.triangle_count % 12, 0u);  // boxes of 6 quads, 24 vertices each
        for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count;
             t += 12) {
          std::uint32_t base = std::numeric_limits<std::uint32_t>::max();
          for (std::uint32_t k = t; k < t + 12; ++k)
            for (const std::uint32_t v : o.mesh->triangles[k])
              base = std::min(base, v);
          Eigen::Vector3d c = Eigen::Vector3d::Zero();
          for (std::uint32_t v = base; v < base + 24; ++v)
            c += o.worldVertex(v) / 24.0;
          centres[{std::lround(std::floor(c.x())), std::lround(std::floor(c.y()))}].push_back(
              c.head<2>());
          ++sleepers;
        }
      }
  const auto found = [&](const Eigen::Vector2d& p) {
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto cell = centres.find(
            {std::lround(std::floor(p.x())) + dx, std::lround(std::floor(p.y())) + dy});
        if (cell != centres.end())
          for (const Eigen::Vector2d& c : cell->second)
            if ((c - p).norm() < 0.05)  // chord sag and the cant's tilt of the sleeper's axis
              return true;
      }
    return false;
  };
  std::size_t expected = 0, missing = 0;
  for (const auto& t : w.railway().layout().tracks) {
    const track::Polyline line = track::samplePolyline(w.railway().main(), t);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
      const double d0 = line.distance_m[k], d1 = line.distance_m[k + 1];
      for (double n = std::ceil(d0 / spacing); n * spacing < d1; n += 1.0) {
        const double u = (n * spacing - d0) / (d1 - d0);
        const Eigen::Vector2d p = ((1.0 - u) * line.points[k] + u * line.points[k + 1]).head<2>();
        ++expected;
        if (!found(p)) {
          ++missing;
          ADD_FAILURE() << "no sleeper on track " << t.id << " at distance " << n * spacing
                        << " m (" << p.transpose() << ")";
          if (missing > 10)
            return;
        }
      }
    }
  }
  EXPECT_GT(expected, 20000u);
  // One each: none twice (a tile border's sleeper made by both tiles).
  EXPECT_NEAR(static_cast<double>(sleepers), static_cast<double>(expected), 3.0);
}

TEST(Assets, TheBallastsToesStandOnTheLevelFormationOnCantedCurves) {
  // The ballast's shoulders tilt with the cant as the sleepers do, but its toes meet the level
  // ground beside the track: both toes of a section at one height, and on the default route's
  // canted curve (2133-2696 m, 105 mm) on the ground beside the single track. Tilted with the
  // cant, one toe floated 0.18 m above the ground and the other lay as deep in it.
  const World& w = defaultWorld();
  const terrain::Terrain& terrain = w.env().terrain();
  const auto along = alongTheMainTrack(w);
  std::size_t sections = 0, on_the_curve = 0;
  double worst_level = 0.0, worst_ground = 0.0;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      if (o.instance != 0 || o.mesh->parts.empty() ||
          o.mesh->parts.front().cls != scene::cls::kTrackbed)
        continue;
      // The ballast's sections: 4 vertices each (toe, shoulder top, shoulder top, toe).
      const scene::MeshPart& bed = o.mesh->parts.front();
      std::uint32_t last = 0;
      for (std::uint32_t t = bed.first_triangle; t < bed.first_triangle + bed.triangle_count; ++t)
        for (const std::uint32_t v : o.mesh->triangles[t])
          last = std::max(last, v);
      for (std::uint32_t k = 0; 4 * k + 3 <= last; ++k) {
        const Eigen::Vector3d a = o.worldVertex(4 * k), b = o.worldVertex(4 * k + 3);
        worst_level = std::max(worst_level, std::abs(a.z() - b.z()));
        ++sections;
        const auto [x, lateral, up] = along(0.5 * (a + b));
        if (std::abs(lateral) > 0.5 || x < 2300.0 || x > 2550.0)
          continue;  // the main track's sections on the curve's full cant
        for (const Eigen::Vector3d& toe : {a, b})
          worst_ground =
              std::max(worst_ground, std::abs(toe.z() - terrain.gridHeightAt(toe.x(), toe.y())));
        ++on_the_curve;
      }
    }
  EXPECT_GT(sections, 5000u);
  EXPECT_GT(on_the_curve, 50u);
  EXPECT_LT(worst_level, 1e-3);
  EXPECT_LT(worst_ground, 0.03);
}

TEST(Assets, FenceStrandsRunFromPostToPostAcrossEveryTileBorder) {
  // Each fence's two strands join every post to the next, whichever tiles the two stand in: the
  // bay across a tile border belongs to the tile of its first post (it was drawn by neither).
  std::map<scene::InstanceId, std::vector<Eigen::Vector3d>> posts;  // their feet
  std::map<scene::InstanceId, std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> bays;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // within 1e-3 near the origin
  for (const auto& tile : allTiles()) {
    for (const auto& o : tile->objects) {
      if (scene::instanceSource(o.instance) != scene::InstanceSource::kTrackAsset ||
          ((o.instance >> 36) & 0xFF) != 11)
        continue;
      for (std::uint32_t first = 0; first + 24 <= o.mesh->vertices.size(); first += 24) {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (std::uint32_t v = first; v < first + 24; ++v)
          c += o.worldVertex(v) / 24.0;
        posts[o.instance].push_back(c - 0.55 * up);  // a post's box: 0.3 m down, 1.4 m up
      }
    }
    for (const scene::Wire& wire : tile->wires)
      if (wire.cls == scene::cls::kFence)
        for (std::size_t k = 0; k + 1 < wire.points.size(); ++k)
          bays[wire.instance].emplace_back(tile->origin + wire.points[k].cast<double>(),
                                           tile->origin + wire.points[k + 1].cast<double>());
  }
  ASSERT_FALSE(posts.empty());
  std::size_t joined = 0;
  for (const auto& [instance, feet] : posts) {
    const auto& spans = bays[instance];
    // Neighbouring posts: 2.5 m of main chainage apart (a little more or less off the axis).
    for (std::size_t i = 0; i < feet.size(); ++i)
      for (std::size_t j = 0; j < feet.size(); ++j) {
        const double apart = (feet[i] - feet[j]).head<2>().norm();
        if (i == j || apart < 1.5 || apart > 3.5 || feet[i].x() > feet[j].x())
          continue;
        for (const double h : {0.5, 1.2}) {
          const Eigen::Vector3d a = feet[i] + h * up, b = feet[j] + h * up;
          const bool drawn = std::any_of(spans.begin(), spans.end(), [&](const auto& s) {
            return ((s.first - a).norm() < 0.01 && (s.second - b).norm() < 0.01) ||
                   ((s.first - b).norm() < 0.01 && (s.second - a).norm() < 0.01);
          });
          EXPECT_TRUE(drawn) << "no strand at " << h << " m between the posts at "
                             << feet[i].transpose() << " and " << feet[j].transpose();
          joined += drawn;
        }
      }
  }
  EXPECT_GT(joined, 1000u);
}

TEST(Objects, StandOnTheLowestGroundUnderTheirFootprintWhereverATilesBorderFalls) {
  // Each object's foot is the lowest ground under its centre and four rim points (of its foot:
  // ObjectKind::foot_share of its footprint), from the height grid of the tile each point lies
  // in. Near a tile's border some rim points lie beyond
  // the object's own tile: they were clamped to its edge, and trees of the default route stood
  // up to 0.25 m above the lowest ground (one at (3043.4, 1.0)). Over km 2.5-3.6 of the route,
  // against each point's own tile's grid.
  const World& w = defaultWorld();
  const terrain::Terrain& terrain = w.env().terrain();
  std::map<scene::TileIndex, terrain::TerrainTile> grids;
  const auto ground = [&](const Eigen::Vector2d& p) {
    const scene::TileIndex i = w.env().grid().tileAt(p.x(), p.y());
    auto it = grids.find(i);
    if (it == grids.end())
      it = grids.emplace(i, terrain.sceneTile(i)).first;
    // Bilinear in the grid cell (the mesh's triangles split it; the placement reads the grid).
    const terrain::TerrainTile& t = it->second;
    const double u = (p.x() - t.origin.x()) / t.spacing_m, v = (p.y() - t.origin.y()) / t.spacing_m;
    const int c = std::min(static_cast<int>(u), t.n - 2),
              r = std::min(static_cast<int>(v), t.n - 2);
    const double fx = u - c, fy = v - r;
    return (1 - fy) * ((1 - fx) * t.height(c, r) + fx * t.height(c + 1, r)) +
           fy * ((1 - fx) * t.height(c, r + 1) + fx * t.height(c + 1, r + 1));
  };
  double worst = 0.0;
  std::size_t by_a_border = 0, checked = 0;
  for (const auto& i : w.env().tiles()) {
    const Eigen::Vector2d lo = w.env().grid().corner(i);
    if (lo.x() < 2500.0 || lo.x() > 3600.0)
      continue;
    for (const auto& o : w.env().objects(i)) {
      double lowest = std::numeric_limits<double>::infinity();
      bool border = false;
      const double foot = o.radius_m * environment::objectKinds()[o.kind].foot_share;
      for (const auto& d :
           {Eigen::Vector2d(0, 0), Eigen::Vector2d(foot, 0), Eigen::Vector2d(-foot, 0),
            Eigen::Vector2d(0, foot), Eigen::Vector2d(0, -foot)}) {
        const Eigen::Vector2d p = o.position.head<2>() + d;
        border = border || !(w.env().grid().tileAt(p.x(), p.y()) == i);
        lowest = std::min(lowest, ground(p));
      }
      worst = std::max(worst, std::abs(o.position.z() - lowest));
      by_a_border += border;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300u);
  EXPECT_GT(by_a_border, 20u);
  EXPECT_LT(worst, 1e-6);
  // A tree stands on the ground under its trunk, not the lowest under its crown: on the slopes
  // by the first tunnel's portals (km 0-0.8) no trunk's foot lies more than half a metre under
  // the ground at its centre (they were sunk up to 2.2 m on the default route).
  double sunk = 0.0;
  std::size_t trees = 0;
  for (const auto& i : w.env().tiles()) {
    const Eigen::Vector2d lo = w.env().grid().corner(i);
    if (lo.x() < 0.0 || lo.x() > 800.0)
      continue;
    for (const auto& o : w.env().objects(i))
      if (environment::objectKinds()[o.kind].name == "trees") {
        sunk = std::max(sunk, ground(o.position.head<2>()) - o.position.z());
        ++trees;
      }
  }
  EXPECT_GT(trees, 100u);
  EXPECT_LT(sunk, 0.5);
  // A point's grid height is its tile's, wherever the point is asked from.
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(3043.4, 1.0), Eigen::Vector2d(3087.25, -30.5),
                                   Eigen::Vector2d(2944.0, 12.125)})
    EXPECT_NEAR(terrain.gridHeightAt(p.x(), p.y()), ground(p), 1e-6);
}

TEST(Objects, FootprintsNeverOverlapAndKeepClearOfEveryTrack) {
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  const auto kinds = environment::objectKinds();
  std::vector<environment::PlacedObject> all;
  for (const auto& i : w.env().tiles()) {
    const auto objects = w.env().objects(i);
    all.insert(all.end(), objects.begin(), objects.end());
  }
  ASSERT_GT(all.size(), 500u);
  PlanGrid grid;
  for (std::size_t k = 0; k < all.size(); ++k)
    grid.add(all[k].position, k);
  std::set<scene::InstanceId> instances;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const auto& o = all[k];
    EXPECT_TRUE(instances.insert(o.instance).second);
    grid.near(o.position, 1, [&](std::size_t j) {
      if (j != k) {
        ASSERT_GE((all[j].position - o.position).head<2>().norm(), all[j].radius_m + o.radius_m)
            << "objects " << k << " and " << j << " overlap";
      }
    });
    // Clear of every track (brute force over all segments, tunnels included), which keeps it
    // off the track bed, platforms, bridge decks, masts and fences (all within 6 m).
    const Nearest open = nearest(segments, o.position.head<2>(), false);
    const Nearest tube = nearest(segments, o.position.head<2>(), true);
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m,
              w.env().params().objects.kinds[o.kind].min_track_distance_m - 1e-9);
    const auto& A = w.env().params().assets;
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m, A.platform_edge_m + A.platform_width_m)
        << kinds[o.kind].name;
    EXPECT_GE(std::min(open.d, tube.d) - o.radius_m, A.fence_offset_m) << kinds[o.kind].name;
  }
}

TEST(Objects, PlacementDoesNotDependOnWhichTilesWereMadeFirst) {
  // A tile's objects are decided from candidates around it only: the same tile from a second
  // environment (nothing made before it) and after all others gives the same list.
  const World& w = defaultWorld();
  const World fresh = makeWorld();
  const scene::TileIndex t =
      *std::next(w.env().tiles().begin(), static_cast<long>(w.env().tiles().size() / 2));
  const auto a = w.env().objects(t);
  const auto b = fresh.env().objects(t);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].instance, b[k].instance);
    EXPECT_EQ(a[k].position, b[k].position);
  }
}

TEST(Assets, UprightThingsStandAlongTheEarthsLocalVerticalNotWorldZ) {
  // World z is up only at the scenario's origin: at the default route's far end the Earth's
  // vertical is tilted 0.9 mrad against it (9° 1000 km out). Trees, rocks, buildings and signals
  // (their placement's z axis), masts and fence posts (the long axis of their boxes, by
  // principal components) must follow the tile's level frame, checked on every tile tilted by
  // more than 0.4 mrad, twenty times the bound.
  constexpr double kBound = 2e-5;
  const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
  };
  const auto longAxis = [](const scene::Object& o, std::uint32_t first) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::uint32_t v = first; v < first + 24; ++v)
      mean += o.worldVertex(v) / 24.0;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (std::uint32_t v = first; v < first + 24; ++v)
      covariance += (o.worldVertex(v) - mean) * (o.worldVertex(v) - mean).transpose();
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(2).eval();
  };
  std::map<std::string, std::size_t> checked;
  for (const auto& tile : allTiles()) {
    const Eigen::Vector3d up = tile->level.col(2);
    if (angle(up, Eigen::Vector3d::UnitZ()) < 20 * kBound)
      continue;
    for (const auto& o : tile->objects) {
      if (o.mesh->prototype) {
        const Eigen::Matrix3d linear = o.linear.cast<double>();
        EXPECT_LT(angle(linear.col(2), up), kBound) << o.instance;
        EXPECT_LT(std::abs(linear.col(0).normalized().dot(up)), kBound) << o.instance;
        ++checked["placed objects"];
        continue;
      }
      if (scene::instanceSource(o.instance) != scene::InstanceSource::kTrackAsset)
        continue;
      const int kind = static_cast<int>((o.instance >> 36) & 0xFF);
      if (kind == 3 && o.mesh->vertices.size() > 24) {  // a mast: its box first (tunnel: hanger)
        EXPECT_LT(angle(longAxis(o, 0), up), kBound) << o.instance;
        ++checked["masts"];
      }
      if (kind == 11)  // fence posts, a box of 24 vertices each
        for (std::uint32_t first = 0; first + 24 <= o.mesh->vertices.size(); first += 24) {
          EXPECT_LT(angle(longAxis(o, first), up), kBound) << o.instance;
          ++checked["fence posts"];
        }
    }
  }
  for (const char* what : {"placed objects", "masts", "fence posts"})
    EXPECT_GT(checked[what], 10u) << what;
}

TEST(Assets, PlatformsStandAtTheirEdgeFromTheTracksAndClearOfAnAuxiliaryTracksLeg) {
  // A station entered by an auxiliary track's dead-end leg, which turns in from 9.6 m to the
  // track's parallel 4 m within the station (as an audit's route had it). Each platform's front
  // face stands platform_edge_m, its back platform_edge_m + platform_width_m, from the nearest
  // track, all along it: the platform follows the parallel tracks and stops short of the leg
  // (it used to stand beyond the leg's far end, 7 m from every track).
  const Json patch = Json::parse(R"({"route": {"source": "blocks", "blocks": [
      {"type": "straight", "length_m": 300},
      {"type": "curve", "length_m": 300, "radius_m": 1200, "direction": "left"},
      {"type": "station", "length_m": 250}, {"type": "straight", "length_m": 300}]}})");
  const World w = makeWorld(patch);
  const environment::AssetParams& A = w.env().params().assets;
  const auto nearest = nearestOn(allSegments(w));
  const track::Layout& layout = w.railway().layout();
  // The scenario does what it is here for: a track's leg lies further out in the station than
  // any track runs parallel there.
  const terrain::Structure* station = nullptr;
  for (const terrain::Structure& s : w.railway().structures())
    if (s.type == track::BlockType::kStation)
      station = &s;
  ASSERT_NE(station, nullptr);
  double leg = 0.0, parallel = 0.0;
  for (const track::LayoutTrack& t : layout.tracks)
    for (const track::OffsetPiece& piece : t.offset)
      if (piece.x1 > station->chainage_begin_m && piece.x0 < station->chainage_end_m) {
        const double x = std::clamp(station->chainage_begin_m, piece.x0, piece.x1);
        leg = std::max(leg, piece.offset(x));
        if (piece.shape == track::OffsetPiece::Shape::kLine && piece.y0 == piece.y1)
          parallel = std::max(parallel, piece.y0);
      }
  ASSERT_GT(leg, parallel + 1.0) << "no leg turns in within the station";
  int front = 0, back = 0, other = 0;
  std::map<int, int> sides;
  for (const scene::TileIndex& i : w.env().tiles()) {
    const std::shared_ptr<const scene::Tile> tile = w.env().tile(i);  // alive through the loop
    for (const auto& o : tile->objects) {
      const auto asset = scene::trackAsset(o.instance);
      if (!asset || (asset->kind != 7 && asset->kind != 8))  // the left and right platforms
        continue;
      for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
        const double side = nearest(o.worldVertex(v))[1], d = std::abs(side);
        // Each platform an instance of its own, on its side (they used to share one).
        EXPECT_EQ(side > 0.0, asset->kind == 7) << "a platform on the wrong side";
        ++sides[asset->kind];
        if (std::abs(d - A.platform_edge_m) < 0.02)
          ++front;
        else if (std::abs(d - A.platform_edge_m - A.platform_width_m) < 0.02)
          ++back;
        else
          ++other;
      }
    }
  }
  EXPECT_GT(front, 0);
  EXPECT_GT(back, 0);
  EXPECT_GT(sides[7], 0);
  EXPECT_GT(sides[8], 0);
  EXPECT_EQ(other, 0) << front << " vertices at the front, " << back << " at the back";
}

TEST(Assets, MastsSignalsAndFencesStayOutOfEveryTracksClearanceGauge) {
  // Below the top of the kinematic gauge (4.35 m above the rails, UIC GB), nothing of a mast,
  // signal or fence comes closer than 2.2 m (plan) to any track centre: the gauge's half-width
  // of about 1.7 m and a margin. The cantilevers reach over the track above it.
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  std::map<std::pair<long, long>, std::vector<const Segment*>> grid;
  for (const auto& s : segments) {
    const Eigen::Vector2d m = 0.5 * (s.a + s.b).head<2>();
    grid[{std::lround(std::floor(m.x() / 20.0)), std::lround(std::floor(m.y() / 20.0))}].push_back(
        &s);
  }
  std::size_t checked = 0;
  for (const auto& tile : allTiles())
    for (const auto& o : tile->objects) {
      if (scene::instanceSource(o.instance) != scene::InstanceSource::kTrackAsset)
        continue;
      const int kind = static_cast<int>((o.instance >> 36) & 0xFF);
      if (kind != 3 && kind != 11 && kind != 12)
        continue;  // masts, fences, signals
      for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
        const Eigen::Vector3d p = o.worldVertex(v);
        double best = std::numeric_limits<double>::infinity(), z = 0.0;
        const long gx = std::lround(std::floor(p.x() / 20.0)),
                   gy = std::lround(std::floor(p.y() / 20.0));
        for (long dx = -1; dx <= 1; ++dx)
          for (long dy = -1; dy <= 1; ++dy) {
            const auto it = grid.find({gx + dx, gy + dy});
            if (it == grid.end())
              continue;
            for (const Segment* s : it->second) {
              const Eigen::Vector2d u = (s->b - s->a).head<2>();
              const double t =
                  std::clamp((p.head<2>() - s->a.head<2>()).dot(u) / u.squaredNorm(), 0.0, 1.0);
              const double d = (p.head<2>() - s->a.head<2>() - t * u).norm();
              if (d < best) {
                best = d;
                z = s->a.z() + t * (s->b.z() - s->a.z());
              }
            }
          }
        if (p.z() > z + 4.35)
          continue;
        ++checked;
        ASSERT_GE(best, 2.2) << "asset kind " << kind << " at " << p.transpose();
      }
    }
  EXPECT_GT(checked, 10000u);
}

TEST(Assets, RailsCatenaryAndSignalsKnowTheirTrackAndWhatStandsByTheLineDoesNot) {
  // trackOf: a rail, a mast, a wire or a signal is its layout track's (a mast or a signal stands
  // nearer to it than to the other of the main and double track; beyond the outermost track,
  // so an auxiliary track can lie between, whose arms hang from it); platforms, tunnels,
  // bridges and fences have none.
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  const auto nearestTrack = [&](const Eigen::Vector3d& p) {
    double best = std::numeric_limits<double>::infinity();
    int track = -1;
    for (const Segment& s : segments) {
      if (s.track > 1)
        continue;  // only the main and double track have masts and signals
      const Eigen::Vector2d u = (s.b - s.a).head<2>();
      const double t = std::clamp((p - s.a).head<2>().dot(u) / u.squaredNorm(), 0.0, 1.0);
      const double d = (p.head<2>() - s.a.head<2>() - t * u).norm();
      if (d < best) {
        best = d;
        track = s.track;
      }
    }
    return track;
  };
  std::map<int, int> checked;  // by asset kind
  for (const auto& tile : allTiles()) {
    for (const auto& o : tile->objects) {
      const auto asset = scene::trackAsset(o.instance);
      if (!asset)
        continue;
      const std::optional<int> track = w.env().trackOf(o.instance);
      const bool by_the_line = asset->kind >= 7 && asset->kind <= 11;
      ASSERT_EQ(track.has_value(), !by_the_line) << asset->kind;
      if (track) {
        ASSERT_EQ(*track, asset->track_id);
      }
      if (asset->kind == 3 && *track > 1) {
        // An auxiliary track's arms (from the mast of the main or double track on its side)
        // reach over it: their far end within the stagger of its centre, in plan.
        double reach = std::numeric_limits<double>::infinity();
        for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v) {
          const Eigen::Vector2d p = o.worldVertex(v).head<2>();
          for (const Segment& s : segments)
            if (s.track == *track) {
              const Eigen::Vector2d u = (s.b - s.a).head<2>();
              const double t = std::clamp((p - s.a.head<2>()).dot(u) / u.squaredNorm(), 0.0, 1.0);
              reach = std::min(reach, (p - s.a.head<2>() - t * u).norm());
            }
        }
        EXPECT_LE(reach, w.env().params().assets.stagger_m + 0.05) << o.position.transpose();
      } else if (asset->kind == 3 || asset->kind == 12) {
        // A mast's or a signal's foot (its vertices within 1 m of its lowest: the cantilevers
        // reach over the tracks) is nearest to its own track.
        double low = std::numeric_limits<double>::infinity();
        for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v)
          low = std::min(low, o.worldVertex(v).z());
        std::map<int, int> votes;
        for (std::uint32_t v = 0; v < o.mesh->vertices.size(); ++v)
          if (const Eigen::Vector3d p = o.worldVertex(v); p.z() < low + 1.0)
            ++votes[nearestTrack(p)];
        EXPECT_EQ(votes.size(), 1u) << asset->kind;
        EXPECT_EQ(votes.begin()->first, *track) << asset->kind << " at " << o.position.transpose();
      }
      ++checked[asset->kind];
    }
    for (const auto& wire : tile->wires) {
      const auto asset = scene::trackAsset(wire.instance);
      ASSERT_TRUE(asset.has_value());
      const std::optional<int> track = w.env().trackOf(wire.instance);
      ASSERT_EQ(track.has_value(), asset->kind != 11) << asset->kind;  // fences' wires: none
      if (track) {
        ASSERT_EQ(*track, asset->track_id);
      }
      ++checked[asset->kind];
    }
  }
  for (const int kind : {1, 2, 3, 4, 5, 12, 7, 8, 9, 10, 11})
    EXPECT_GT(checked[kind], 0) << "no asset of kind " << kind;
  EXPECT_FALSE(w.env().trackOf(scene::objectInstance(1, 2, 3)).has_value());
}

}  // namespace
}  // namespace trainsim
