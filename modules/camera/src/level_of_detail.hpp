#pragma once
// Levels of detail for the cameras: lighter versions of a mesh by vertex clustering.
#include <cmath>

#include "trainsim/scene/mesh.hpp"

namespace trainsim::camera {

// Levels of detail: level L ≥ 1 merges the mesh's vertices in cubic cells of side
// kFinestCell_m · 2^(L−1) (mesh units), dropping the triangles that collapse
// (clustered()); level 0 is the mesh itself.
inline constexpr int kLevels = 5;
inline constexpr double kFinestCell_m = 0.05;
inline double cellSize(int level) {
  return kFinestCell_m * std::ldexp(1.0, level - 1);
}

// A lighter level of a mesh by vertex clustering (Rossignac and Borrel): the vertices in each
// cubic cell of side `cell` merge into one at their mean, and the triangles left with fewer
// than three corners go; parts (class, material) are kept. No vertex moves by more than the
// cell's diagonal. Written here rather than taken from VTK: vtkBinnedDecimation and
// vtkQuadricClustering keep dense arrays over every cell of the mesh's box (a 250 m terrain
// tile at 5 cm is 10⁹ cells, gigabytes to clear per mesh), where a hash of the occupied cells
// costs what the mesh has. Sequential and in vertex order, so the result is a pure function of
// the mesh.
scene::Mesh clustered(const scene::Mesh& mesh, double cell);

}  // namespace trainsim::camera
