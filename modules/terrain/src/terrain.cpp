#include "trainsim/terrain/terrain.hpp"

#include "plan_distance.hpp"
#include "skirt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/png.hpp"

namespace trainsim::terrain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRegionalStep_m = 25.0;  // lattice of the regional level, and its track samples
constexpr double kRegionalSoftening_m = 25.0;

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

double quintic(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}
double linear(double t) {
  return t;
}

// Values on the nodes of the global square lattice of `step` that cover a box, interpolated
// bilinearly between the four nodes around a point (the fractions passed through `fade`). The
// nodes are global (node i at i·step), so every box that covers a point gives it the same value.
class Lattice {
 public:
  template <typename NodeValue>
  Lattice(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double step, NodeValue value)
      : step_(step),
        i0_(static_cast<std::int64_t>(std::floor(lo.x() / step))),
        j0_(static_cast<std::int64_t>(std::floor(lo.y() / step))),
        width_(static_cast<std::int64_t>(std::floor(hi.x() / step)) + 2 - i0_) {
    const std::int64_t rows = static_cast<std::int64_t>(std::floor(hi.y() / step)) + 2 - j0_;
    values_.resize(static_cast<std::size_t>(width_ * rows));
    for (std::int64_t j = 0; j < rows; ++j)
      for (std::int64_t i = 0; i < width_; ++i)
        values_[static_cast<std::size_t>(j * width_ + i)] = value(i0_ + i, j0_ + j);
  }
  double at(double x, double y, double (*fade)(double)) const {
    const double u = x / step_, v = y / step_;
    const auto i = static_cast<std::int64_t>(std::floor(u));
    const auto j = static_cast<std::int64_t>(std::floor(v));
    const double fx = fade(u - static_cast<double>(i)), fy = fade(v - static_cast<double>(j));
    const auto base = static_cast<std::size_t>((j - j0_) * width_ + (i - i0_));
    const auto w = static_cast<std::size_t>(width_);
    const double bottom = values_[base] + fx * (values_[base + 1] - values_[base]);
    const double top = values_[base + w] + fx * (values_[base + w + 1] - values_[base + w]);
    return bottom + fy * (top - bottom);
  }

 private:
  double step_;
  std::int64_t i0_, j0_, width_;
  std::vector<double> values_;
};

}  // namespace

// A rectangular grid of vertices being filled: vertex (c, r) at world x = (gx + c)·spacing,
// y = (gy + r)·spacing for the tile's global vertex indices, or one vertex at a given point.
struct Terrain::Field {
  double x0 = 0.0, y0 = 0.0;  // world position of vertex (0, 0)
  std::int64_t gx = 0, gy = 0;
  bool global = true;  // positions from global indices (tiles) or from x0, y0 (one point)
  double spacing = 1.0;
  int nx = 1, ny = 1;
  std::vector<double> d_open, z_open, d_station, z_station, d_tunnel, z_tunnel, far, noise, valley,
      height;
  std::vector<std::uint8_t> bore;
  std::vector<float> skirt;

  double x(int c) const { return global ? static_cast<double>(gx + c) * spacing : x0; }
  double y(int r) const { return global ? static_cast<double>(gy + r) * spacing : y0; }
  std::size_t at(int c, int r) const { return static_cast<std::size_t>(r) * nx + c; }
};

Terrain::Terrain(std::shared_ptr<const Railway> railway, TerrainParams params, std::uint64_t seed)
    : railway_(std::move(railway)), params_(params), seed_(seed) {
  if (params_.scene_tile_split < 1 || (params_.tile_vertices - 1) % params_.scene_tile_split != 0)
    throw ConfigError("terrain.scene_tile_split must divide terrain.tile_vertices - 1");
  const double margin = params_.tile_margin_m;
  for (const Railway::RunBox& box : railway_->runBoxes()) {
    throwIfCancelled();
    const track::Polyline line = railway_->polyline({box.track, box.x0, box.x1});
    for (const auto& p : line.points)
      for (const auto& [g, set] : {std::pair{grid(), &tiles_}, {sceneGrid(), &scene_tiles_}}) {
        const scene::TileIndex lo = g.tileAt(p.x() - margin, p.y() - margin);
        const scene::TileIndex hi = g.tileAt(p.x() + margin, p.y() + margin);
        for (std::int32_t i = lo.i; i <= hi.i; ++i)
          for (std::int32_t j = lo.j; j <= hi.j; ++j)
            if (g.distance({i, j}, p.head<2>()) <= margin)
              set->insert({i, j});
      }
  }
}

void Terrain::fill(Field& f) const {
  const TerrainParams& P = params_;
  const std::size_t count = static_cast<std::size_t>(f.nx) * f.ny;
  f.d_open.assign(count, kInf);
  f.z_open.assign(count, 0.0);
  f.d_station.assign(count, kInf);
  f.z_station.assign(count, 0.0);
  f.d_tunnel.assign(count, kInf);
  f.z_tunnel.assign(count, 0.0);
  const Eigen::Vector2d lo(f.x(0), f.y(0)), hi(f.x(f.nx - 1), f.y(f.ny - 1));

  // 1. Nearest track point by splatting every segment near the field onto the vertices within
  // its reach (exact plan distances, no per-vertex scan of segments). Segments come in track
  // then chainage order and a tie keeps the first, so a vertex gets the same answer in every
  // tile that contains it.
  const double reach_open = std::max(P.d_far_m, P.d_near_station_m);
  // A station's track counts as `widen` nearer (step 5), so its blend reaches that much further.
  const double widen = std::max(0.0, P.d_near_station_m - P.d_near_m);
  const double reach_station = std::max(reach_open, P.d_far_m + widen);
  const double reach_tunnel =
      P.tunnel_half_width_m + (P.tunnel_crown_m + P.tunnel_cover_m) / P.hill_slope;
  const double reach = std::max(reach_station, reach_tunnel);
  for (const Stretch& s : railway_->stretchesNear(lo, hi, reach + f.spacing)) {
    throwIfCancelled();
    const track::Polyline line = railway_->polyline(s);
    for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
      const Eigen::Vector3d& a = line.points[k];
      const Eigen::Vector3d& b = line.points[k + 1];
      const auto type =
          railway_->typeAt(s.track, 0.5 * (line.distance_m[k] + line.distance_m[k + 1]));
      const bool tunnel = type == track::LayoutBlockType::kTunnel;
      const bool station = type == track::LayoutBlockType::kStation;
      const double r = tunnel ? reach_tunnel : station ? reach_station : reach_open;
      // Vertex index range covering the segment's box grown by its reach.
      const auto col = [&](double x) { return (x - lo.x()) / f.spacing; };
      const auto row = [&](double y) { return (y - lo.y()) / f.spacing; };
      const int c0 = std::max(0, static_cast<int>(std::floor(col(std::min(a.x(), b.x()) - r))));
      const int c1 =
          std::min(f.nx - 1, static_cast<int>(std::ceil(col(std::max(a.x(), b.x()) + r))));
      const int r0 = std::max(0, static_cast<int>(std::floor(row(std::min(a.y(), b.y()) - r))));
      const int r1 =
          std::min(f.ny - 1, static_cast<int>(std::ceil(row(std::max(a.y(), b.y()) + r))));
      for (int rr = r0; rr <= r1; ++rr)
        for (int cc = c0; cc <= c1; ++cc) {
          double t = 0.0;
          const double d = detail::segmentDistance(f.x(cc), f.y(rr), a.x(), a.y(), b.x(), b.y(), t);
          if (d > r)
            continue;
          const std::size_t i = f.at(cc, rr);
          const double z = a.z() + t * (b.z() - a.z());
          if (tunnel) {
            if (d < f.d_tunnel[i]) {
              f.d_tunnel[i] = d;
              f.z_tunnel[i] = z;
            }
          } else {
            if (d < f.d_open[i] && d <= reach_open) {
              f.d_open[i] = d;
              f.z_open[i] = z;
            }
            if (station && d < f.d_station[i]) {
              f.d_station[i] = d;
              f.z_station[i] = z;
            }
          }
        }
    }
  }

  // 2. The regional level: formation heights of track points every 25 m of main chainage,
  // inverse-distance weighted on a global 25 m lattice (same points, same order for every
  // lattice node whatever the field), bilinearly interpolated at the vertices.
  struct Coarse {
    double x, y, z;
  };
  std::vector<Coarse> coarse;
  const double R = P.regional_radius_m;
  for (const Stretch& s : railway_->stretchesNear(lo, hi, R + 2.0 * kRegionalStep_m + 10.0)) {
    const auto& t = railway_->layout().tracks.at(s.track);
    const double x_begin = std::max(s.x0, t.main_chainage_begin_m);
    const double x_end = std::min(s.x1, t.main_chainage_end_m);
    for (double k = std::ceil(x_begin / kRegionalStep_m); k * kRegionalStep_m < x_end; k += 1.0) {
      const Eigen::Vector3d p = railway_->frame(s.track, k * kRegionalStep_m).position;
      coarse.push_back({p.x(), p.y(), p.z() - P.formation_depth_m});
    }
  }
  const auto lattice_value = [&](double qx, double qy) {
    double sw = 0.0, swz = 0.0, best = kInf, best_z = 0.0;
    for (const Coarse& c : coarse) {
      const double d2 = (c.x - qx) * (c.x - qx) + (c.y - qy) * (c.y - qy);
      if (d2 < best) {
        best = d2;
        best_z = c.z;
      }
      if (d2 >= R * R)
        continue;
      const double fall = 1.0 - d2 / (R * R);
      const double w = fall * fall / (d2 + kRegionalSoftening_m * kRegionalSoftening_m);
      sw += w;
      swz += w * c.z;
    }
    return sw > 0.0 ? swz / sw : best_z;
  };
  const Lattice regional(lo, hi, kRegionalStep_m, [&](std::int64_t i, std::int64_t j) {
    return lattice_value(static_cast<double>(i) * kRegionalStep_m,
                         static_cast<double>(j) * kRegionalStep_m);
  });

  // 3. Fractal value noise on global lattices, one per octave; lattice values from the
  // counter-based stream "terrain/noise" keyed by (lattice node, octave).
  f.far.assign(count, 0.0);
  f.noise.assign(count, 0.0);
  const RandomStream stream(seed_, "terrain/noise");
  double norm = 0.0;
  for (int o = 0; o < P.octaves; ++o)
    norm += std::pow(P.persistence, o);
  for (int o = 0; o < P.octaves; ++o) {
    const double wavelength = P.wavelength_m / std::pow(2.0, o);
    const double amplitude = P.amplitude_m * std::pow(P.persistence, o) / norm;
    const Lattice nodes(lo, hi, wavelength, [&](std::int64_t i, std::int64_t j) {
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) |
                                static_cast<std::uint32_t>(j);
      return 2.0 * stream.uniform4(key, static_cast<std::uint64_t>(o))[0] - 1.0;
    });
    for (int r = 0; r < f.ny; ++r)
      for (int c = 0; c < f.nx; ++c)
        f.noise[f.at(c, r)] += amplitude * nodes.at(f.x(c), f.y(r), quintic);
  }
  for (int r = 0; r < f.ny; ++r)
    for (int c = 0; c < f.nx; ++c)
      f.far[f.at(c, r)] = regional.at(f.x(c), f.y(r), linear) + f.noise[f.at(c, r)];

  // 4. Valleys under bridges: across each bridge's chord, full depth between the abutment ramps
  // (slope 1:1.5) and within valley_width_m of the bridge's middle, fading out to twice that.
  f.valley.assign(count, 0.0);
  for (const Structure& s : railway_->structures()) {
    if (s.type != track::BlockType::kBridge)
      continue;
    const Eigen::Vector2d& a = s.begin_xy;
    const Eigen::Vector2d& b = s.end_xy;
    const double length = (b - a).norm();
    if (length <= 0.0)
      continue;
    const Eigen::Vector2d t = (b - a) / length, n(-t.y(), t.x()), mid = 0.5 * (a + b);
    const double extent = 0.5 * length + 2.0 * P.valley_width_m;
    if (mid.x() + extent < lo.x() || mid.x() - extent > hi.x() || mid.y() + extent < lo.y() ||
        mid.y() - extent > hi.y())
      continue;
    const double ramp = std::min(0.25 * length, 1.5 * P.valley_depth_m);
    for (int r = 0; r < f.ny; ++r)
      for (int c = 0; c < f.nx; ++c) {
        const Eigen::Vector2d q(f.x(c) - mid.x(), f.y(r) - mid.y());
        const double along = std::abs(q.dot(t)), across = std::abs(q.dot(n));
        if (along >= 0.5 * length)
          continue;
        const double depth = P.valley_depth_m * std::min(1.0, (0.5 * length - along) / ramp) *
                             (1.0 - smoothstep(P.valley_width_m, 2.0 * P.valley_width_m, across));
        double& v = f.valley[f.at(c, r)];
        v = std::max(v, depth);
      }
  }

  // 5. The paper's blend, then the ground over tunnels (cut at the portals) and the valleys.
  f.height.assign(count, 0.0);
  f.bore.assign(count, 0);
  f.skirt.assign(count, 0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    // The distance the blend follows: to the nearest track, or to the nearest station track
    // less `widen` (stations keep d_near_station_m of formation for their platforms), whichever
    // is less. Both are continuous in the plane, so the ground has no step where a station
    // ends; a flag of the nearest track point's block made one (1.2 m at the default route's).
    double d = f.d_open[i], z = f.z_open[i];
    if (f.d_station[i] - widen < d) {
      d = f.d_station[i] - widen;
      z = f.z_station[i];
    }
    const double d_near = P.d_near_m;
    const double formation = z - P.formation_depth_m;
    double h;
    if (d <= d_near)
      h = formation;
    else if (d >= P.d_far_m)
      h = f.far[i];
    else {
      const double w = (d - d_near) / (P.d_far_m - d_near);
      h = (1.0 - w) * formation + w * f.far[i];
    }
    if (f.d_tunnel[i] < kInf) {
      const double hill = f.z_tunnel[i] + P.tunnel_crown_m + P.tunnel_cover_m -
                          P.hill_slope * std::max(0.0, f.d_tunnel[i] - P.tunnel_half_width_m);
      const double cut = d < kInf ? formation + P.cut_slope * std::max(0.0, d - d_near) : kInf;
      h = std::max(h, std::min(hill, cut));
    }
    f.height[i] = h - f.valley[i];
    // In the bore: nearer a tunnel's track than any open track (so past the portal, not in
    // front of it), within the tube's half width, and below its crown.
    f.bore[i] = f.d_tunnel[i] < P.tunnel_half_width_m && f.d_tunnel[i] < f.d_open[i] &&
                f.height[i] < f.z_tunnel[i] + P.tunnel_crown_m;
    // In front of the portal (nearer the open track), beside the cut: a skirt down to a metre
    // under the formation. (Never inside: a skirt from the ground over the tube would hang
    // across the bore.)
    if (f.d_open[i] <= f.d_tunnel[i] && f.d_tunnel[i] < P.tunnel_half_width_m + 2.0 * f.spacing)
      f.skirt[i] = static_cast<float>(
          std::max(0.0, f.height[i] - (f.z_open[i] - P.formation_depth_m) + 1.0));
  }
}

TerrainTile Terrain::tile(scene::TileIndex index) const {
  return square(index, params_.tile_vertices);
}

TerrainTile Terrain::sceneTile(scene::TileIndex index) const {
  return square(index, (params_.tile_vertices - 1) / params_.scene_tile_split + 1);
}

TerrainTile cropTile(const TerrainTile& tile, scene::TileIndex index, int split) {
  const int n = (tile.n - 1) / split + 1;
  const int c0 = (index.i - tile.index.i * split) * (n - 1);
  const int r0 = (index.j - tile.index.j * split) * (n - 1);
  if (c0 < 0 || r0 < 0 || c0 + n > tile.n || r0 + n > tile.n)
    throw std::logic_error("cropTile: the scene tile is not inside the terrain tile");
  TerrainTile t;
  t.index = index;
  t.n = n;
  t.spacing_m = tile.spacing_m;
  t.origin = tile.origin + tile.spacing_m * Eigen::Vector2d(c0, r0);
  t.heights.reserve(static_cast<std::size_t>(n) * n);
  t.bore.reserve(static_cast<std::size_t>(n) * n);
  t.skirt.reserve(static_cast<std::size_t>(n) * n);
  for (int r = 0; r < n; ++r) {
    const auto first = static_cast<std::ptrdiff_t>(r0 + r) * tile.n + c0;
    t.heights.insert(t.heights.end(), tile.heights.begin() + first,
                     tile.heights.begin() + first + n);
    t.bore.insert(t.bore.end(), tile.bore.begin() + first, tile.bore.begin() + first + n);
    t.skirt.insert(t.skirt.end(), tile.skirt.begin() + first, tile.skirt.begin() + first + n);
  }
  t.z0 = std::floor(*std::min_element(t.heights.begin(), t.heights.end()));
  return t;
}

TerrainTile Terrain::square(scene::TileIndex index, int n) const {
  Field f;
  f.spacing = params_.spacing_m;
  f.nx = f.ny = n;
  f.gx = static_cast<std::int64_t>(index.i) * (n - 1);
  f.gy = static_cast<std::int64_t>(index.j) * (n - 1);
  fill(f);
  TerrainTile t;
  t.index = index;
  t.n = n;
  t.spacing_m = params_.spacing_m;
  t.origin = {f.x(0), f.y(0)};
  t.z0 = std::floor(*std::min_element(f.height.begin(), f.height.end()));
  t.heights = std::move(f.height);
  t.bore = std::move(f.bore);
  t.skirt = std::move(f.skirt);
  return t;
}

double Terrain::gridHeightAt(double x, double y) const {
  // The grid cell holding the point, filled as a tile holding it fills it.
  Field f;
  f.spacing = params_.spacing_m;
  f.nx = f.ny = 2;
  f.gx = static_cast<std::int64_t>(std::floor(x / f.spacing));
  f.gy = static_cast<std::int64_t>(std::floor(y / f.spacing));
  fill(f);
  const double fx = std::clamp(x / f.spacing - static_cast<double>(f.gx), 0.0, 1.0);
  const double fy = std::clamp(y / f.spacing - static_cast<double>(f.gy), 0.0, 1.0);
  return (1 - fy) * ((1 - fx) * f.height[0] + fx * f.height[1]) +
         fy * ((1 - fx) * f.height[2] + fx * f.height[3]);
}

double Terrain::heightAt(double x, double y, HeightParts* parts) const {
  Field f;
  f.global = false;
  f.x0 = x;
  f.y0 = y;
  f.spacing = params_.spacing_m;
  fill(f);
  if (parts) {
    *parts = {f.d_open[0],   f.z_open[0], f.d_station[0], f.z_station[0], f.d_tunnel[0],
              f.z_tunnel[0], f.far[0],    f.noise[0],     f.valley[0]};
  }
  return f.height[0];
}

scene::Mesh terrainMesh(const TerrainTile& tile, const Eigen::Vector3d& origin,
                        scene::MaterialId material) {
  scene::Mesh mesh;
  const int n = tile.n;
  mesh.vertices.reserve(static_cast<std::size_t>(n) * n);
  const Eigen::Vector3d base(tile.origin.x() - origin.x(), tile.origin.y() - origin.y(),
                             -origin.z());
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      mesh.addVertex(Eigen::Vector3f(
          static_cast<float>(base.x() + c * tile.spacing_m),
          static_cast<float>(base.y() + r * tile.spacing_m),
          static_cast<float>(base.z() + tile.heights[static_cast<std::size_t>(r) * n + c])));
  mesh.triangles.reserve(2 * static_cast<std::size_t>(n - 1) * (n - 1));
  mesh.beginPart(scene::cls::kTerrain, material);
  // Cell (c, r) is cut when a corner lies in a tunnel's bore (no cell outside the tile is).
  const auto cut = [&](int c, int r) {
    return c >= 0 && r >= 0 && c + 1 < n && r + 1 < n &&
           (tile.inBore(c, r) || tile.inBore(c + 1, r) || tile.inBore(c, r + 1) ||
            tile.inBore(c + 1, r + 1));
  };
  bool whole = true;
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      if (cut(c, r)) {
        whole = false;
        continue;
      }
      const auto v = static_cast<std::uint32_t>(r * n + c);
      const auto un = static_cast<std::uint32_t>(n);
      // Split along (c+1, r)–(c, r+1), as Embree splits a grid's cells (Mesh::grid_columns).
      mesh.addQuad(v + 1, v + un + 1, v + un, v);
    }
  // An Embree grid has no holes: a tile at a portal stays triangles, with skirts where a kept
  // cell borders a cut one.
  mesh.grid_columns = whole ? static_cast<std::uint32_t>(n) : 0u;
  if (!whole) {
    const auto edge = [&](int c0, int r0, int c1, int r1) {
      detail::addSkirt(mesh, static_cast<std::uint32_t>(r0 * n + c0),
                       static_cast<std::uint32_t>(r1 * n + c1), tile.skirtAt(c0, r0),
                       tile.skirtAt(c1, r1));
    };
    for (int r = 0; r + 1 < n; ++r)
      for (int c = 0; c + 1 < n; ++c) {
        if (cut(c, r))
          continue;
        if (cut(c, r - 1))
          edge(c, r, c + 1, r);
        if (cut(c, r + 1))
          edge(c, r + 1, c + 1, r + 1);
        if (cut(c - 1, r))
          edge(c, r, c, r + 1);
        if (cut(c + 1, r))
          edge(c + 1, r, c + 1, r + 1);
      }
  }
  return mesh;
}

}  // namespace trainsim::terrain

namespace trainsim::terrain {

void writeHeightPng(const TerrainTile& tile, const std::filesystem::path& png) {
  double top = 0.0;
  for (const double h : tile.heights)
    top = std::max(top, h - tile.z0);
  // 1 cm steps, coarser only for tiles taller than 655 m.
  const double scale = std::max(0.01, top / 65535.0);
  std::vector<std::uint16_t> pixels(tile.heights.size());
  // PNG rows run top to bottom: the image's top row is the tile's northern edge (largest y).
  for (int r = 0; r < tile.n; ++r)
    for (int c = 0; c < tile.n; ++c) {
      const double v = std::round((tile.height(c, r) - tile.z0) / scale);
      pixels[static_cast<std::size_t>(tile.n - 1 - r) * tile.n + c] =
          static_cast<std::uint16_t>(std::clamp(v, 0.0, 65535.0));
    }
  io::writeFileAtomic(png,
                      io::encodePngGray16(tile.n, tile.n, pixels, io::PngContent::kMeasurement));
  nlohmann::json meta = {
      {"tile", {tile.index.i, tile.index.j}},
      {"size", tile.n},
      {"spacing_m", tile.spacing_m},
      {"origin_m", {tile.origin.x(), tile.origin.y()}},
      {"z0_m", tile.z0},
      {"scale_m", scale},
      {"rows", "top row = largest y (north); height = z0_m + value * scale_m; world ENU"}};
  std::filesystem::path json_path = png;
  json_path.replace_extension(".json");
  io::writeFileAtomic(json_path, meta.dump(2) + "\n");
}

}  // namespace trainsim::terrain
