#pragma once
// Private to the LiDAR module: scene geometry handed to Embree — meshes as triangles, height
// fields as Embree grids, and wires as exact capsules in a user geometry.
#include <embree3/rtcore.h>
#include <Eigen/Geometry>

#include <vector>

#include "trainsim/scene/scene.hpp"

namespace trainsim::lidar::detail {

/// Adds `mesh` to `scene` as one triangle geometry, each vertex v placed at
/// offset + level · (linear · v) (summed in double, stored in float).
void addTriangles(RTCDevice device, RTCScene scene, const scene::Mesh& mesh,
                  const Eigen::Vector3d& offset, const Eigen::Matrix3f& linear,
                  const Eigen::Matrix3d& level = Eigen::Matrix3d::Identity());

/// Adds a height field (Mesh::grid_columns) to `scene` as one Embree grid: the vertices and a
/// grid record, no triangles; Embree splits each cell along the diagonal the mesh's triangles
/// use. A hit's primID is the grid's (0), so it takes the mesh's only part. Throws RuntimeError
/// for a mesh that is not such a height field of one part.
void addGrid(RTCDevice device, RTCScene scene, const scene::Mesh& mesh,
             const Eigen::Vector3d& offset, const Eigen::Matrix3d& level);

/// A wire's points (double) and radius, kept for as long as its user geometry is cast into.
struct WireData {
  std::vector<Eigen::Vector3d> points;
  double radius = 0.0;
};

/// Adds `wire` to `scene` as a user geometry of exact capsules (a cylinder of the wire's radius
/// between two points, spheres at the ends) intersected in double, its points turned by `level`;
/// `data` keeps them.
void addWire(RTCDevice device, RTCScene scene, const scene::Wire& wire,
             const Eigen::Matrix3d& level, WireData& data);

}  // namespace trainsim::lidar::detail
