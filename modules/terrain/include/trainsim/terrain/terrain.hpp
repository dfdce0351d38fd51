#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "trainsim/scene/mesh.hpp"
#include "trainsim/scene/scene.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim::terrain {

/// The landscape generator's parameters (the paper's §Landscape Generation, with the valleys,
/// tunnel cover and cuts it describes). Lengths in m.
struct TerrainParams {
  double spacing_m = 1.0;        ///< between height-map vertices
  int tile_vertices = 1009;      ///< per side of a tile (the paper's 1009 × 1009)
  double tile_margin_m = 400.0;  ///< tiles within this plan distance of a track exist
  double d_near_m = 3.5;         ///< within this of a track the ground is at its formation
  /// The same in stations (room for platforms): a station's track counts as
  /// d_near_station_m − d_near_m nearer, so the ground leaves the formation smoothly past the
  /// station's ends rather than with a step.
  double d_near_station_m = 12.0;
  double d_far_m = 30.0;            ///< beyond this the ground is the noise height
  double formation_depth_m = 0.75;  ///< top of rail down to the ground under the ballast
  // Fractal value noise: octaves of halving wavelength and `persistence`-scaled amplitude.
  int octaves = 5;
  double amplitude_m = 8.0;
  double wavelength_m = 500.0;
  double persistence = 0.5;
  /// The level the noise rides on: the tracks' formation height, inverse-distance weighted over
  /// points every 25 m of every track within this radius, so the far ground follows the route's
  /// climbs and falls.
  double regional_radius_m = 2500.0;
  double valley_depth_m = 12.0;      ///< below the formation under the middle of a bridge
  double valley_width_m = 120.0;     ///< half-width of a valley's full depth across the track
  double tunnel_crown_m = 7.5;       ///< tunnel crown (top of the tube) above top of rail
  double tunnel_cover_m = 5.0;       ///< ground above the crown
  double tunnel_half_width_m = 7.0;  ///< of the tube's outside around the tracks
  double cut_slope = 1.0;            ///< rise per metre of the cutting sides at tunnel portals
  double hill_slope = 0.6;           ///< fall per metre of the ground beside a tunnel
  /// Terrain meshes simplified to this vertical error (CGAL greedy-insertion TIN); 0 keeps the
  /// full grid.
  double simplify_tolerance_m = 0.02;
  /// The scene streams in squares this many times finer than the terrain tiles (a terrain
  /// tile's side splits into this many scene tiles): small enough that the tiles within a
  /// sensor's reach hold little more than what it can see. Divides tile_vertices - 1.
  int scene_tile_split = 4;

  double tileSize() const { return spacing_m * (tile_vertices - 1); }
  double sceneTileSize() const { return tileSize() / scene_tile_split; }
};

/// The height map of one tile: tile_vertices² heights (world z, double), row-major with x
/// fastest, vertex (c, r) at world (origin.x + c·spacing, origin.y + r·spacing). A pure function
/// of (railway, params, seed, index): bit-identical in any order, on any thread; a tile's border
/// vertices equal its neighbours' exactly (meshes hold them in float relative to each tile's
/// own origin, so there they agree to the float's rounding, about 10 µm).
struct TerrainTile {
  scene::TileIndex index;
  int n = 0;
  double spacing_m = 1.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double z0 = 0.0;  ///< a whole metre at or below the lowest height (the tile origin's z)
  std::vector<double> heights;
  /// 1 where the vertex lies in a tunnel's bore, below its crown: the cutting in front of a
  /// portal rises over the tunnel's first metres, and a height field cannot hold the opening a
  /// portal is, so the meshes leave out every cell with a corner here (the tube and the portal
  /// ring close the gap). Same size as `heights`.
  std::vector<std::uint8_t> bore;
  /// How far a skirt hangs under each vertex where the mesh's edge borders the cut, in front of
  /// a portal (0 elsewhere): down to a metre under the formation, so that no line of sight
  /// through the opening passes under the height field beside the portal. Same size as
  /// `heights`.
  std::vector<float> skirt;

  double height(int c, int r) const { return heights[static_cast<std::size_t>(r) * n + c]; }
  bool inBore(int c, int r) const { return bore[static_cast<std::size_t>(r) * n + c] != 0; }
  float skirtAt(int c, int r) const { return skirt[static_cast<std::size_t>(r) * n + c]; }
  Eigen::Vector3d vertex(int c, int r) const {
    return {origin.x() + c * spacing_m, origin.y() + r * spacing_m, height(c, r)};
  }
};

/// What decided a vertex's height (for tests and previews).
struct HeightParts {
  double d_open = 0.0;     ///< plan distance to the nearest track outside tunnels (inf: none near)
  double z_open = 0.0;     ///< that track point's height (top of rail)
  double d_station = 0.0;  ///< plan distance to the nearest track in a station (inf: none near)
  double z_station = 0.0;
  double d_tunnel = 0.0;  ///< plan distance to the nearest track in a tunnel (inf: none near)
  double z_tunnel = 0.0;
  double far = 0.0;  ///< regional level + noise
  double noise = 0.0;
  double valley = 0.0;  ///< depth cut by bridge valleys (≥ 0)
};

/// The part of `tile` under the square of scene tile `index` (Terrain::sceneGrid(), which splits
/// the tile's side into `split`): the same heights, bit for bit, as Terrain::sceneTile(index).
TerrainTile cropTile(const TerrainTile& tile, scene::TileIndex index, int split);

/// The landscape: which tiles exist and each tile's heights, in the terrain grid and in the finer
/// grid the scene streams in.
class Terrain {
 public:
  Terrain(std::shared_ptr<const Railway> railway, TerrainParams params, std::uint64_t seed);

  const TerrainParams& params() const { return params_; }
  scene::TileGrid grid() const { return {params_.tileSize()}; }
  /// Tiles within tile_margin_m of any track (from the railway's run boxes and a finer check
  /// on each run's points).
  const std::set<scene::TileIndex>& tiles() const { return tiles_; }

  /// The tile's heights.
  TerrainTile tile(scene::TileIndex index) const;

  /// The scene's grid: squares of sceneTileSize(), each inside one terrain tile.
  scene::TileGrid sceneGrid() const { return {params_.sceneTileSize()}; }
  /// Scene tiles within tile_margin_m of any track (a subset of the terrain tiles' squares).
  const std::set<scene::TileIndex>& sceneTiles() const { return scene_tiles_; }
  /// A scene tile's heights ((tile_vertices - 1) / scene_tile_split + 1 per side): the same
  /// values as the terrain tile holding it has there.
  TerrainTile sceneTile(scene::TileIndex index) const;
  /// The height at one world point, by the same rules as tile() (not from a tile: it builds a
  /// small index around the point), and what decided it.
  double heightAt(double x, double y, HeightParts* parts = nullptr) const;
  /// The height the tiles' grids give at one world point (bilinear in the grid cell holding it,
  /// as terrainHeight() over a tile): the same wherever the tiles' borders fall, as a grid
  /// vertex's height is the same in every tile holding it.
  double gridHeightAt(double x, double y) const;

  const Railway& railway() const { return *railway_; }

 private:
  struct Field;
  void fill(Field& field) const;
  TerrainTile square(scene::TileIndex index, int n) const;

  std::shared_ptr<const Railway> railway_;
  TerrainParams params_;
  std::uint64_t seed_;
  std::set<scene::TileIndex> tiles_, scene_tiles_;
};

/// The tile as a triangle mesh (two triangles per cell, none for a cell touching the bore),
/// vertices relative to `origin`; a height field (scene::Mesh::grid_columns) when no cell is
/// left out.
scene::Mesh terrainMesh(const TerrainTile& tile, const Eigen::Vector3d& origin,
                        scene::MaterialId material);

/// The tile as a triangulated irregular network within `tolerance_m` of every grid height
/// (vertical error, exact by construction): greedy insertion of the worst grid point into a
/// Delaunay triangulation in plan (CGAL), every border vertex kept so tiles still meet exactly,
/// and every bore vertex with its neighbours, so the opening is cut out along the same cells as
/// terrainMesh() cuts it.
/// Counter-clockwise from above; the same bytes for the same tile.
struct SimplifiedMesh {
  scene::Mesh mesh;
  double max_error_m = 0.0;  ///< the largest vertical distance of a grid point from the mesh
};
SimplifiedMesh simplifiedTerrainMesh(const TerrainTile& tile, const Eigen::Vector3d& origin,
                                     scene::MaterialId material, double tolerance_m);

/// Writes the tile as a 16-bit greyscale PNG (value v: height z0 + v·scale, scale 1 cm or more
/// for tall tiles) plus a JSON file with the same stem holding index, size, spacing, origin,
/// z0 and scale. Both atomically.
void writeHeightPng(const TerrainTile& tile, const std::filesystem::path& png);

}  // namespace trainsim::terrain
