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

/// Writes a height grid as VTK image data (.vti) for ParaView: n × n points at `origin` (x, y)
/// with `spacing`, point array `height_m` (world z, double), to be shown with Warp By Scalar.
/// Atomic (temporary file, then renamed); throws IoError naming the file.
void writeHeightVti(const std::filesystem::path& vti, int n, const Eigen::Vector2d& origin,
                    double spacing_m, std::span<const double> heights);

}  // namespace trainsim::scene
