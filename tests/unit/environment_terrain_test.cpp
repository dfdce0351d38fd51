// The terrain against independent references: its rules recomputed by brute force over every
// track segment, the noise from the random stream, the regional level by hand; determinism
// across tile orders and threads; the PNG read back; the simplified mesh checked point by point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "trainsim/core/random.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/terrain/daylight.hpp"

#include "unit/environment_world.hpp"

namespace trainsim {
namespace {

using scenario::Json;

// Value noise as the terrain's docs define it, written again from the random stream.
double referenceNoise(const terrain::TerrainParams& P, std::uint64_t seed, double x, double y) {
  const RandomStream stream(seed, "terrain/noise");
  double norm = 0.0, sum = 0.0;
  for (int o = 0; o < P.octaves; ++o)
    norm += std::pow(P.persistence, o);
  for (int o = 0; o < P.octaves; ++o) {
    const double wl = P.wavelength_m / std::pow(2.0, o);
    const double u = x / wl, v = y / wl;
    const double i = std::floor(u), j = std::floor(v);
    const auto node = [&](double a, double b) {
      const std::uint64_t key =
          (static_cast<std::uint64_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(a)))
           << 32) |
          static_cast<std::uint32_t>(static_cast<std::int64_t>(b));
      return 2.0 * stream.uniform4(key, static_cast<std::uint64_t>(o))[0] - 1.0;
    };
    const auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    const double fx = fade(u - i), fy = fade(v - j);
    const double bottom = node(i, j) + fx * (node(i + 1, j) - node(i, j));
    const double top = node(i, j + 1) + fx * (node(i + 1, j + 1) - node(i, j + 1));
    sum += P.amplitude_m * std::pow(P.persistence, o) / norm * (bottom + fy * (top - bottom));
  }
  return sum;
}

TEST(Terrain, HeightsFollowTheBlendAgainstABruteForceReference) {
  const World& w = defaultWorld();
  const auto segments = allSegments(w);
  const terrain::TerrainParams& P = w.env().params().terrain;
  const RandomStream pick(7, "test.terrain.points");
  int near = 0, blend = 0, far = 0, station = 0;
  for (std::uint64_t k = 0; k < 1500; ++k) {
    // Points along the route, up to 60 m to either side, away from bridges and tunnels.
    const auto u = pick.uniform4(k);
    const double x = u[0] * w.railway().main().length();
    const track::TrackFrame f = w.railway().frame(0, x);
    const Eigen::Vector2d p =
        f.position.head<2>() + (120.0 * u[1] - 60.0) * f.left.head<2>().normalized();
    terrain::HeightParts parts;
    const double h = w.env().terrain().heightAt(p.x(), p.y(), &parts);
    if (parts.valley != 0.0 || std::isfinite(parts.d_tunnel))
      continue;
    const Nearest n = nearest(segments, p, false);
    const Nearest ns = nearestStation(segments, p);
    const double reach = std::max(P.d_far_m, P.d_near_station_m);
    const double widen = std::max(0.0, P.d_near_station_m - P.d_near_m);
    if (n.d <= reach) {
      ASSERT_NEAR(parts.d_open, n.d, 1e-9);
      ASSERT_NEAR(parts.z_open, n.z, 1e-9);
    }
    if (ns.d <= P.d_far_m + widen) {
      ASSERT_NEAR(parts.d_station, ns.d, 1e-9);
      ASSERT_NEAR(parts.z_station, ns.z, 1e-9);
      ++station;
    }
    EXPECT_NEAR(parts.noise, referenceNoise(P, w.scenario.seed(), p.x(), p.y()), 1e-9);
    // A station's track counts as `widen` nearer than it is.
    const bool by_station = ns.d - widen < n.d;
    const double d = by_station ? ns.d - widen : n.d;
    const double formation = (by_station ? ns.z : n.z) - P.formation_depth_m;
    if (d <= P.d_near_m) {
      ++near;
      EXPECT_NEAR(h, formation, 1e-9);
    } else if (d >= P.d_far_m) {
      ++far;
      EXPECT_NEAR(h, parts.far, 1e-9);
    } else {
      ++blend;
      const double wgt = (d - P.d_near_m) / (P.d_far_m - P.d_near_m);
      EXPECT_NEAR(h, (1 - wgt) * formation + wgt * parts.far, 1e-9);
    }
  }
  EXPECT_GT(near, 50);
  EXPECT_GT(blend, 300);
  EXPECT_GT(far, 300);
  EXPECT_GT(station, 20);
}

// Where a station ends the ground leaves its wider formation smoothly: along lines beside the
// main track across each station's ends, no step between heights 0.5 m apart beyond what the
// blend's own slope gives. (Deciding the formation's width by the block of the nearest track
// point made a step there: 1.2 m at 12 m from the default route's station.)
TEST(Terrain, NoStepWhereAStationEnds) {
  const World& w = defaultWorld();
  int ends = 0;
  double worst = 0.0;
  for (const terrain::Structure& s : w.railway().structures()) {
    if (s.type != track::BlockType::kStation)
      continue;
    for (const double end : {s.chainage_begin_m, s.chainage_end_m}) {
      ++ends;
      for (const double lateral : {-20.0, -14.0, -11.0, -8.0, 8.0, 11.0, 14.0, 20.0}) {
        double previous = std::numeric_limits<double>::quiet_NaN();
        for (double x = end - 40.0; x <= end + 40.0; x += 0.5) {
          const track::TrackFrame f = w.railway().frame(0, x);
          const Eigen::Vector2d p = f.position.head<2>() + lateral * f.left.head<2>().normalized();
          terrain::HeightParts parts;
          const double h = w.env().terrain().heightAt(p.x(), p.y(), &parts);
          if (parts.valley != 0.0 || std::isfinite(parts.d_tunnel)) {
            previous = std::numeric_limits<double>::quiet_NaN();
            continue;
          }
          if (!std::isnan(previous))
            worst = std::max(worst, std::abs(h - previous));
          previous = h;
        }
      }
    }
  }
  EXPECT_GT(ends, 0);
  // The blend's slope: the ground's gap between formation and noise height over the blend's
  // 26.5 m, times the 0.5 m step (and the noise's own slope): a few centimetres.
  EXPECT_LT(worst, 0.15) << "largest change between neighbours 0.5 m apart";
}

TEST(Terrain, TheRegionalLevelIsTheWeightedTrackFormation) {
  // Far from the track, height − noise is the inverse-distance weighted formation height of
  // track points every 25 m, bilinear between 25 m lattice nodes: checked at a lattice node.
  const World& w = defaultWorld();
  const terrain::TerrainParams& P = w.env().params().terrain;
  const track::TrackFrame f = w.railway().frame(0, 2400.0);
  const Eigen::Vector2d q = (f.position.head<2>() + 200.0 * f.left.head<2>().normalized()) / 25.0;
  const Eigen::Vector2d node(std::round(q.x()) * 25.0, std::round(q.y()) * 25.0);
  terrain::HeightParts parts;
  w.env().terrain().heightAt(node.x(), node.y(), &parts);
  double sw = 0.0, swz = 0.0;
  for (const auto& t : w.railway().layout().tracks)
    for (double k = std::ceil(t.main_chainage_begin_m / 25.0); k * 25.0 < t.main_chainage_end_m;
         k += 1.0) {
      const Eigen::Vector3d p = w.railway().frame(t.id, k * 25.0).position;
      const double d2 = (p.head<2>() - node).squaredNorm();
      if (d2 >= P.regional_radius_m * P.regional_radius_m)
        continue;
      const double fall = 1.0 - d2 / (P.regional_radius_m * P.regional_radius_m);
      const double wt = fall * fall / (d2 + 625.0);
      sw += wt;
      swz += wt * (p.z() - P.formation_depth_m);
    }
  EXPECT_NEAR(parts.far - parts.noise, swz / sw, 1e-6);
}

TEST(Terrain, ValleysUnderBridgesAndGroundOverTunnels) {
  const World& w = defaultWorld();
  const terrain::TerrainParams& P = w.env().params().terrain;
  int bridges = 0, tunnels = 0;
  for (const terrain::Structure& s : w.railway().structures()) {
    const double inset =
        s.type == track::BlockType::kBridge ? 0.25 * (s.chainage_end_m - s.chainage_begin_m) : 40.0;
    for (double x = s.chainage_begin_m + inset; x <= s.chainage_end_m - inset; x += 10.0)
      for (const double lateral : {-6.0, -2.0, 0.0, 2.0, 6.0}) {
        const track::TrackFrame f = w.railway().frame(0, x);
        const Eigen::Vector2d p = f.position.head<2>() + lateral * f.left.head<2>().normalized();
        const double h = w.env().terrain().heightAt(p.x(), p.y());
        if (s.type == track::BlockType::kBridge) {
          ++bridges;  // room for a river: the ground well below the deck (1.5 m under the
                      // formation)
          EXPECT_LT(h, f.position.z() - P.formation_depth_m - 1.5 - 3.0) << "bridge at " << x;
        } else if (s.type == track::BlockType::kTunnel) {
          ++tunnels;  // the tube (crown tunnel_crown_m above the rails) runs underground
          EXPECT_GE(h, f.position.z() + P.tunnel_crown_m + 0.5 * P.tunnel_cover_m)
              << "tunnel at " << x;
        }
      }
  }
  EXPECT_GT(bridges, 10);
  EXPECT_GT(tunnels, 100);
}

// The triangles (world, double) of class `cls` in the scene tiles within `reach` of `at`.
std::vector<std::array<Eigen::Vector3d, 3>> trianglesNear(const World& w, const Eigen::Vector3d& at,
                                                          double reach, scene::ClassId cls) {
  std::vector<std::array<Eigen::Vector3d, 3>> out;
  const scene::TileGrid grid = w.env().grid();
  const scene::TileIndex lo = grid.tileAt(at.x() - reach, at.y() - reach);
  const scene::TileIndex hi = grid.tileAt(at.x() + reach, at.y() + reach);
  for (std::int32_t i = lo.i; i <= hi.i; ++i)
    for (std::int32_t j = lo.j; j <= hi.j; ++j) {
      if (!w.env().terrain().sceneTiles().contains({i, j}))
        continue;
      const std::shared_ptr<const scene::Tile> tile = w.env().tile({i, j});
      for (const scene::Object& o : tile->objects)
        for (const scene::MeshPart& part : o.mesh->parts) {
          if (part.cls != cls)
            continue;
          for (std::uint32_t k = part.first_triangle; k < part.first_triangle + part.triangle_count;
               ++k) {
            const auto& t = o.mesh->triangles[k];
            out.push_back({o.worldVertex(t[0]), o.worldVertex(t[1]), o.worldVertex(t[2])});
          }
        }
    }
  return out;
}

// The heights at which the triangles' surfaces pass over plan point p; with `facing` −1 only
// those facing down (counter-clockwise seen from below), +1 only those facing up.
std::vector<double> heightsOver(const std::vector<std::array<Eigen::Vector3d, 3>>& triangles,
                                const Eigen::Vector2d& p, int facing = 0) {
  std::vector<double> out;
  for (const auto& v : triangles) {
    const Eigen::Vector2d a = v[0].head<2>(), b = v[1].head<2>(), c = v[2].head<2>();
    const double area = (b - a).x() * (c - a).y() - (c - a).x() * (b - a).y();
    if (area == 0.0 || area * facing < 0.0)
      continue;  // a vertical face, or one facing the other way
    const double u = ((c - b).x() * (p - b).y() - (c - b).y() * (p - b).x()) / area;
    const double t = ((a - c).x() * (p - c).y() - (a - c).y() * (p - c).x()) / area;
    if (u >= 0.0 && t >= 0.0 && u + t <= 1.0)
      out.push_back(u * v[0].z() + t * v[1].z() + (1.0 - u - t) * v[2].z());
  }
  return out;
}

TEST(Terrain, TheTunnelPortalsAreOpenAndTheTubesClosed) {
  // The train's clearance through each portal (10 m in front to 30 m inside, 1.6 m either side
  // of the track, 0.3 to 5 m above the rails) holds no ground: the scene's terrain triangles
  // are searched, point by point of that space's plan, for a surface inside it. (Before the
  // bore was cut out, the cutting's 1:1 slope ran across the first metres of every tunnel.)
  // Inside, the tube has a floor from wall to wall: no line of sight to the sky below it.
  const World& w = defaultWorld();
  const terrain::TerrainParams& P = w.env().params().terrain;
  int portals = 0, samples = 0, floor_samples = 0;
  for (const terrain::Structure& s : w.railway().structures()) {
    if (s.type != track::BlockType::kTunnel)
      continue;
    for (const double portal : {s.chainage_begin_m, s.chainage_end_m}) {
      ++portals;
      const double inward = portal == s.chainage_begin_m ? 1.0 : -1.0;
      const Eigen::Vector3d at = w.railway().frame(0, portal).position;
      const auto ground = trianglesNear(w, at, 60.0, scene::cls::kTerrain);
      const auto tube = trianglesNear(w, at, 60.0, scene::cls::kTunnel);
      ASSERT_FALSE(ground.empty());
      ASSERT_FALSE(tube.empty());
      for (double along = -10.0; along <= 30.0; along += 0.5)
        for (double lateral = -1.6; lateral <= 1.6; lateral += 0.4) {
          const track::TrackFrame f = w.railway().frame(0, portal + inward * along);
          const Eigen::Vector2d p = f.position.head<2>() + lateral * f.left.head<2>().normalized();
          ++samples;
          for (const double z : heightsOver(ground, p))
            EXPECT_FALSE(z > f.position.z() + 0.3 && z < f.position.z() + 5.0)
                << "ground " << z - f.position.z() << " m above the rails " << along
                << " m inside the portal at " << portal << ", " << lateral << " m across";
        }
      // No ground face of any slope (the cut's skirts are vertical) crosses lines along the
      // track through the clearance: Möller–Trumbore against every terrain triangle.
      const Eigen::Vector3d out_at = w.railway().frame(0, portal - inward * 10.0).position;
      const Eigen::Vector3d in_at = w.railway().frame(0, portal + inward * 30.0).position;
      const track::TrackFrame mid = w.railway().frame(0, portal);
      for (const double lateral : {-1.2, 0.0, 1.2})
        for (const double height : {0.5, 2.5, 4.5}) {
          const Eigen::Vector3d offset = lateral * mid.left + height * mid.up;
          const Eigen::Vector3d o = out_at + offset, d = in_at + offset - o;
          for (const auto& v : ground) {
            const Eigen::Vector3d e1 = v[1] - v[0], e2 = v[2] - v[0], p = d.cross(e2);
            const double det = e1.dot(p);
            if (std::abs(det) < 1e-12)
              continue;
            const Eigen::Vector3d from = o - v[0], q = from.cross(e1);
            const double u = from.dot(p) / det, t = d.dot(q) / det, along = e2.dot(q) / det;
            EXPECT_FALSE(u >= 0.0 && t >= 0.0 && u + t <= 1.0 && along >= 0.0 && along <= 1.0)
                << "ground across the track " << height << " m above the rails, " << lateral
                << " m across, " << along * 40.0 - 10.0 << " m inside the portal at " << portal;
          }
        }
      // Wherever the tube's roof is overhead, its floor is underfoot (the lining's roof, facing
      // down into the tube: the shell over the first metres faces up, out of it).
      for (const double along : {5.0, 20.0})
        for (double lateral = -11.9; lateral <= 12.0; lateral += 0.25) {  // not on a wall
          const track::TrackFrame f = w.railway().frame(0, portal + inward * along);
          const Eigen::Vector2d p = f.position.head<2>() + lateral * f.left.head<2>().normalized();
          bool roof = false, floor = false;
          for (const double z : heightsOver(tube, p, -1))
            roof = roof || z > f.position.z() + 1.0;
          for (const double z : heightsOver(tube, p))
            floor = floor || std::abs(z - (f.position.z() - P.formation_depth_m)) < 0.05;
          if (!roof)
            continue;
          ++floor_samples;
          EXPECT_TRUE(floor) << "no floor " << along << " m inside the portal at " << portal << ", "
                             << lateral << " m across";
        }
    }
  }
  EXPECT_EQ(portals, 4);  // the default route's two tunnels
  EXPECT_GT(samples, 2500);
  EXPECT_GT(floor_samples, 150);
}

TEST(Terrain, ATileIsTheSameAloneInAnyOrderOnAnyThreadAndAgreesWithItsNeighbours) {
  const World& w = defaultWorld();
  const auto& tiles = w.env().terrain().tiles();
  ASSERT_GE(tiles.size(), 4u);
  const scene::TileIndex first = *tiles.begin(), last = *tiles.rbegin();
  const terrain::TerrainTile alone = w.env().terrain().tile(last);
  std::vector<terrain::TerrainTile> in_order;
  for (const auto& t : tiles)
    in_order.push_back(w.env().terrain().tile(t));
  terrain::TerrainTile threaded;
  std::thread([&] { threaded = w.env().terrain().tile(last); }).join();
  for (const auto* other : {&in_order.back(), &threaded}) {
    ASSERT_EQ(other->heights.size(), alone.heights.size());
    EXPECT_EQ(std::memcmp(other->heights.data(), alone.heights.data(),
                          alone.heights.size() * sizeof(double)),
              0);
    EXPECT_EQ(other->z0, alone.z0);
  }
  // Shared borders: a tile's east column is its east neighbour's west column.
  int shared = 0;
  for (const auto& t : in_order)
    for (const auto& u : in_order)
      if (u.index.i == t.index.i + 1 && u.index.j == t.index.j) {
        ++shared;
        for (int r = 0; r < t.n; ++r)
          ASSERT_EQ(t.height(t.n - 1, r), u.height(0, r));
        ASSERT_EQ(t.vertex(t.n - 1, 0), u.vertex(0, 0));
      }
  EXPECT_GT(shared, 0);
  (void)first;
}

TEST(Terrain, SceneTilesAreTheTerrainTilesCutExactly) {
  // Made on their own, the finer scene tiles hold bit for bit the heights of the terrain tile
  // around them, and cover every terrain tile's square near a track.
  const World& w = defaultWorld();
  const int split = w.env().params().terrain.scene_tile_split;
  ASSERT_GT(split, 1);
  EXPECT_DOUBLE_EQ(w.env().grid().size_m * split, w.env().terrain().grid().size_m);
  int compared = 0;
  for (const auto& index : w.env().terrain().tiles()) {
    if (compared >= 12)
      break;
    const terrain::TerrainTile whole = w.env().terrain().tile(index);
    for (std::int32_t j = index.j * split; j < (index.j + 1) * split; ++j)
      for (std::int32_t i = index.i * split; i < (index.i + 1) * split; ++i) {
        if (!w.env().tiles().contains({i, j}))
          continue;
        const terrain::TerrainTile alone = w.env().terrain().sceneTile({i, j});
        const terrain::TerrainTile cut = terrain::cropTile(whole, {i, j}, split);
        ASSERT_EQ(alone.n, (whole.n - 1) / split + 1);
        ASSERT_EQ(cut.heights.size(), alone.heights.size());
        EXPECT_EQ(std::memcmp(cut.heights.data(), alone.heights.data(),
                              alone.heights.size() * sizeof(double)),
                  0);
        EXPECT_EQ(cut.origin, alone.origin);
        EXPECT_EQ(cut.z0, alone.z0);
        ++compared;
      }
  }
  EXPECT_GE(compared, 12);
  // Every scene tile lies in an existing terrain tile.
  for (const auto& t : w.env().tiles())
    EXPECT_TRUE(w.env().terrain().tiles().contains(
        {static_cast<std::int32_t>(std::floor(static_cast<double>(t.i) / split)),
         static_cast<std::int32_t>(std::floor(static_cast<double>(t.j) / split))}));
}

TEST(Terrain, HeightPngRoundTrips) {
  const World& w = defaultWorld();
  const terrain::TerrainTile t = w.env().terrain().tile(*w.env().terrain().tiles().begin());
  const auto dir = std::filesystem::temp_directory_path() / "trainsim_height_png";
  std::filesystem::create_directories(dir);
  terrain::writeHeightPng(t, dir / "tile.png");
  const io::PngImage png = io::decodePng(io::readFile(dir / "tile.png"));
  const auto meta = Json::parse(io::readFile(dir / "tile.json"));
  ASSERT_EQ(png.depth, 16);
  ASSERT_EQ(png.width, t.n);
  const double scale = meta["scale_m"].get<double>(), z0 = meta["z0_m"].get<double>();
  for (int r = 0; r < t.n; r += 17)
    for (int c = 0; c < t.n; c += 13)
      EXPECT_NEAR(z0 + scale * png.samples16[static_cast<std::size_t>(t.n - 1 - r) * t.n + c],
                  t.height(c, r), 0.5 * scale + 1e-6);
  std::filesystem::remove_all(dir);
}

TEST(Terrain, TheSimplifiedMeshStaysWithinItsToleranceOfEveryGridHeight) {
  // Brute force: every grid point is located in the simplified mesh by scanning all its
  // triangles, and its height compared with the triangle's plane.
  const World w = makeWorld({{"terrain", {{"tile_vertices", 65}}}});
  // The first tiles, and tiles at the tunnels' portals (with bore vertices).
  int tiles = 0, portal_tiles = 0;
  for (const auto& index : w.env().terrain().tiles()) {
    const terrain::TerrainTile t = w.env().terrain().tile(index);
    const bool portal = std::find(t.bore.begin(), t.bore.end(), 1) != t.bore.end();
    if (portal ? ++portal_tiles > 4 : ++tiles > 4)
      continue;
    const Eigen::Vector3d origin(t.origin.x(), t.origin.y(), t.z0);
    for (const double tol : {0.02, 0.25}) {
      const terrain::SimplifiedMesh s =
          terrain::simplifiedTerrainMesh(t, origin, scene::mat::kGrass, tol);
      EXPECT_LE(s.max_error_m, tol);
      EXPECT_LT(s.mesh.triangles.size(), 2u * 64 * 64);
      double worst = 0.0;
      for (int r = 0; r < t.n; ++r)
        for (int c = 0; c < t.n; ++c) {
          const Eigen::Vector2d p(c * t.spacing_m, r * t.spacing_m);
          bool found = false;
          for (const auto& tri : s.mesh.triangles) {
            Eigen::Vector3d v[3];
            for (int k = 0; k < 3; ++k)
              v[k] = s.mesh.vertices[tri[k]].cast<double>();
            const double area = (v[1] - v[0]).head<2>().x() * (v[2] - v[0]).head<2>().y() -
                                (v[2] - v[0]).head<2>().x() * (v[1] - v[0]).head<2>().y();
            if (v[0].head<2>() == v[1].head<2>() || v[1].head<2>() == v[2].head<2>() ||
                v[2].head<2>() == v[0].head<2>())
              continue;            // a skirt at a portal's cut: vertical
            ASSERT_GT(area, 0.0);  // counter-clockwise from above
            const auto edge = [&](int a, int b) {
              return ((v[b] - v[a]).x() * (p.y() - v[a].y()) -
                      (v[b] - v[a]).y() * (p.x() - v[a].x())) /
                     area;
            };
            const double l0 = edge(1, 2), l1 = edge(2, 0), l2 = edge(0, 1);
            if (l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6)
              continue;
            found = true;
            const double plane = l0 * v[0].z() + l1 * v[1].z() + l2 * v[2].z();
            worst = std::max(worst, std::abs(t.height(c, r) - t.z0 - plane));
            break;
          }
          // A tunnel's bore is cut out: its points, and only they, may lie outside the mesh.
          bool by_bore = false;
          for (int rr = std::max(r - 1, 0); rr <= std::min(r + 1, t.n - 1); ++rr)
            for (int cc = std::max(c - 1, 0); cc <= std::min(c + 1, t.n - 1); ++cc)
              by_bore = by_bore || t.inBore(cc, rr);
          ASSERT_TRUE(found || by_bore) << "grid point " << c << ", " << r << " outside the mesh";
          if (t.inBore(c, r)) {
            EXPECT_FALSE(found) << "bore point " << c << ", " << r << " under the mesh";
          }
        }
      EXPECT_LE(worst, tol + 1e-4);  // float vertices
    }
  }
  EXPECT_GE(portal_tiles, 4);
}

TEST(TunnelDaylight, FadesFromEachPortalIntoTheBoreAndLeavesTheOpenAndTheHillInDaylight) {
  // The default route's two tunnels (double track through both): on either track, daylight
  // falls linearly from 1 at a portal to 0 at 50 m inside, from both ends; in front of a portal,
  // on the hill over the tube and beside it, it is daylight.
  const World& w = defaultWorld();
  const terrain::TerrainParams& p = w.env().params().terrain;
  const terrain::TunnelDaylight day(w.railway().route(), w.railway().layout(), p);
  ASSERT_FALSE(day.empty());
  int tunnels = 0;
  for (const track::Block& b : w.railway().route().blocks) {
    if (b.type != track::BlockType::kTunnel)
      continue;
    ++tunnels;
    ASSERT_GT(b.chainage_end_m - b.chainage_begin_m, 120.0);
    for (const double in : {-10.0, 0.5, 5.0, 25.0, 49.0, 60.0})
      for (const int end : {0, 1})
        for (const int track : {0, 1}) {
          const double s = end == 0 ? b.chainage_begin_m + in : b.chainage_end_m - in;
          const track::TrackFrame f = w.railway().frame(track, s);
          const double expected = std::clamp(1.0 - in / 50.0, 0.0, 1.0);
          // On the rails, and up under the crown.
          for (const double up : {0.2, p.tunnel_crown_m - 0.2})
            EXPECT_NEAR(day(f.position + up * f.up), in < 0.0 ? 1.0 : expected, 1e-3)
                << b.id << " " << s << " track " << track << " up " << up;
        }
    const double mid = 0.5 * (b.chainage_begin_m + b.chainage_end_m);
    const track::TrackFrame f = w.railway().frame(0, mid);
    EXPECT_EQ(day(f.position), 0.0);
    EXPECT_EQ(day(f.position + (p.tunnel_crown_m + 2.0) * f.up), 1.0);  // the hill over it
    // Beside the tube: past the half width left of the main track, and right of the double.
    EXPECT_EQ(day(f.position + (p.tunnel_half_width_m + 1.0) * f.left), 1.0);
    const track::TrackFrame g = w.railway().frame(1, mid);
    EXPECT_EQ(day(g.position - (p.tunnel_half_width_m + 1.0) * g.left), 1.0);
    EXPECT_EQ(day(g.position - (p.tunnel_half_width_m - 1.0) * g.left), 0.0);
  }
  EXPECT_EQ(tunnels, 2);
  // Many points at once (the renderer's way, each nearest sample looked for from the last
  // one's): the same shares, for points along, across and over the whole route.
  std::vector<Eigen::Vector3d> points;
  for (double s = 0.0; s < 6000.0; s += 7.3)
    for (const double across : {-13.0, -6.0, 0.0, 5.0, 9.0})
      for (const double up : {-1.0, 0.3, 4.0, 7.2, 9.0}) {
        const track::TrackFrame f = w.railway().frame(0, s);
        points.push_back(f.position + across * f.left + up * f.up);
      }
  std::vector<float> shares(points.size());
  day.shares(points, shares);
  int shaded = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(shares[i], day(points[i]), 1e-4) << i;
    shaded += shares[i] < 1.0f;
  }
  EXPECT_GT(shaded, 300);
  // A box holding a point out of full daylight meets the shade; boxes far from any bore do not.
  for (std::size_t i = 0; i < points.size(); ++i)
    if (shares[i] < 1.0f) {
      scene::Box3d box;
      box.extend(points[i] - Eigen::Vector3d(0.1, 0.2, 0.3));
      box.extend(points[i] + Eigen::Vector3d(0.3, 0.2, 0.1));
      EXPECT_TRUE(day.meets(box)) << i;
    }
  for (const track::Block& b : w.railway().route().blocks) {
    if (b.type != track::BlockType::kTunnel)
      continue;
    for (const double s : {b.chainage_begin_m - 40.0, b.chainage_end_m + 40.0}) {
      const track::TrackFrame f = w.railway().frame(0, s);
      scene::Box3d box;
      box.extend(f.position - Eigen::Vector3d::Constant(5.0));
      box.extend(f.position + Eigen::Vector3d::Constant(5.0));
      EXPECT_FALSE(day.meets(box)) << "in front of a portal at " << s;
      box.extend(w.railway().frame(0, s < b.chainage_end_m ? s + 60.0 : s - 60.0).position);
      EXPECT_TRUE(day.meets(box)) << "reaching into the bore from " << s;
    }
  }
  EXPECT_FALSE(day.meets(scene::Box3d{}));
  // A route without tunnels has daylight everywhere.
  const World open =
      makeWorld(Json::parse(R"({"route": {"generator": {"tunnel": {"probability": 0}}}})"));
  EXPECT_TRUE(terrain::TunnelDaylight(open.railway().route(), open.railway().layout(),
                                      open.env().params().terrain)
                  .empty());
}

}  // namespace
}  // namespace trainsim
