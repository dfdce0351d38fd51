#pragma once
// The generated scene as VTK poly data, for the pictures of trainsim-scene-shot and the
// studio's scene view: one place that turns tiles into what VTK draws.
#include <vtkSmartPointer.h>

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "trainsim/scene/scene.hpp"

class vtkPolyData;

namespace trainsim::app {

/// What a surface is coloured by: its material's colour (as a camera sees it) or its semantic
/// class's colour (as the labels have it).
enum class SceneColour { kMaterial, kClass };

/// Tiles as two poly data sets relative to `origin` (world, double; the float VTK points stay
/// accurate near it): `surfaces`, every triangle of every object and tile mesh with a colour per
/// cell, and `wires`, every wire as a polyline with a colour per cell.
struct ScenePolyData {
  vtkSmartPointer<vtkPolyData> surfaces, wires;
  long long triangles = 0;
};
ScenePolyData scenePolyData(const std::vector<std::shared_ptr<const scene::Tile>>& tiles,
                            const Eigen::Vector3d& origin,
                            SceneColour colour = SceneColour::kMaterial);

}  // namespace trainsim::app
