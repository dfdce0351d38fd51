// Private to the environment module: the object-position generator.
#pragma once

#include <vector>

#include "trainsim/environment/environment.hpp"

namespace trainsim::environment::detail {

/// The trackside objects anchored in tile `index`, heights from `heights` (the tile's terrain;
/// null: z = 0).
std::vector<PlacedObject> placeObjects(const Environment& env, scene::TileIndex index,
                                       const terrain::TerrainTile* heights);
/// Bilinear terrain height inside a tile.
double terrainHeight(const terrain::TerrainTile& tile, const Eigen::Vector2d& p);

}  // namespace trainsim::environment::detail
