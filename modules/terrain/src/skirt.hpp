#pragma once
// The skirts that close a terrain mesh's cut in front of a tunnel portal (TerrainTile::skirt).
#include <cstdint>

#include "trainsim/scene/mesh.hpp"

namespace trainsim::terrain::detail {

// A vertical quad under mesh edge a–b, down by `depth_a` and `depth_b` (the larger for both, so
// the skirt's foot is level with the lower reach); nothing when both are 0.
inline void addSkirt(scene::Mesh& mesh, std::uint32_t a, std::uint32_t b, float depth_a,
                     float depth_b) {
  const float depth = depth_a > depth_b ? depth_a : depth_b;
  if (!(depth > 0.0f))
    return;
  Eigen::Vector3f foot_a = mesh.vertices[a], foot_b = mesh.vertices[b];
  foot_a.z() -= depth;
  foot_b.z() -= depth;
  const std::uint32_t fa = mesh.addVertex(foot_a), fb = mesh.addVertex(foot_b);
  mesh.addQuad(a, b, fb, fa);
}

}  // namespace trainsim::terrain::detail
