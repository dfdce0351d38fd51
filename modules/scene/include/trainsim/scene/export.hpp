#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include <Eigen/Core>

#include "trainsim/scene/scene.hpp"

namespace trainsim::scene {

/// Writes tiles as a VTK multiblock file for ParaView: `vtm` plus a folder of the same stem with
/// one .vtp per tile (triangles of every object, wires as polylines). Cell arrays `class`,
/// `instance` (uint64), `material` and `radius_m` (wires; 0 for triangles), so ParaView colours
/// by them; points are double, relative to `origin` (field data `origin_m`). Written into a
/// staging folder beside `vtm` and renamed into place, so no half-written file set remains.
/// Throws IoError naming the file if writing fails.
void writeVtm(std::span<const std::shared_ptr<const Tile>> tiles, const std::filesystem::path& vtm,
              const Eigen::Vector3d& origin);

}  // namespace trainsim::scene
