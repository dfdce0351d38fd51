#pragma once
// Small analytic scenes for the perception sensors' tests (LiDAR, cameras): squares at known
// places and a tile holding them, so both sensors are tested against the same geometry.
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "trainsim/scene/scene.hpp"

namespace trainsim::test {

/// A square of side 2·half centred at `centre` (relative to the tile origin) with unit normal n,
/// counter-clockwise seen from the side n points to.
inline scene::Mesh square(const Eigen::Vector3d& centre, const Eigen::Vector3d& n, double half,
                          scene::ClassId cls = scene::cls::kBuilding,
                          scene::MaterialId mat = scene::mat::kConcrete) {
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  scene::Mesh m;
  m.beginPart(cls, mat);
  const auto at = [&](double a, double b) {
    return m.addVertex((centre + half * (a * u + b * v)).cast<float>());
  };
  m.addQuad(at(-1, -1), at(1, -1), at(1, 1), at(-1, 1));
  return m;
}

/// A tile at `origin` whose own meshes (instances 1, 2, … in order) are `meshes`, with `wires`
/// and further placed `objects`.
inline std::shared_ptr<const scene::Tile> makeTile(const Eigen::Vector3d& origin,
                                                   std::vector<scene::Mesh> meshes,
                                                   std::vector<scene::Wire> wires = {},
                                                   std::vector<scene::Object> objects = {}) {
  auto tile = std::make_shared<scene::Tile>();
  tile->origin = origin;
  scene::InstanceId id = 1;
  for (auto& m : meshes)
    tile->objects.push_back(scene::Object::place(std::make_shared<const scene::Mesh>(std::move(m)),
                                                 origin, Eigen::Matrix3f::Identity(), id++));
  for (auto& o : objects)
    tile->objects.push_back(std::move(o));
  tile->wires = std::move(wires);
  tile->updateBounds();
  return tile;
}

}  // namespace trainsim::test
