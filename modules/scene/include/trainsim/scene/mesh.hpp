#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::scene {

/// An axis-aligned box in double precision (world coordinates).
struct Box3d {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  bool empty() const { return !(min.x() <= max.x()); }
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Box3d& b) {
    if (b.empty())
      return;
    extend(b.min);
    extend(b.max);
  }
  /// Plan (x, y) distance from p to the box, 0 inside.
  double planDistance(const Eigen::Vector2d& p) const;
};

/// A run of triangles of a mesh that share a class and a material.
struct MeshPart {
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  ClassId cls = cls::kUnlabelled;
  MaterialId material = mat::kNone;
};

/// Triangles in single precision relative to the mesh's own origin (a tile's origin, or the
/// foot of a prototype), outward-facing counter-clockwise. Parts tile the triangle list in
/// order. Shared by every object that uses it (a tree prototype is stored once).
struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<MeshPart> parts;
  /// > 0 for a height field: the vertices are a row-major grid this many columns wide, each
  /// cell split along its (x+1, y)–(x, y+1) diagonal, one part (the full-resolution terrain).
  /// The LiDAR may hand it to Embree as grid geometry (RayWorldOptions::terrain_grids).
  std::uint32_t grid_columns = 0;
  /// A prototype placed by many objects (a tree, a signal): a ray caster builds its BVH once and
  /// instances it. Any other mesh (a tile's terrain, rails, a bridge) belongs to one object and
  /// goes into its tile's BVH. Set by whoever makes the mesh, never read off how many hold it at
  /// the moment: that depends on which thread got there first (a camera holding a tile's bridge
  /// made the LiDAR instance it, and a 1-thread run's intensities differ in the last bit).
  bool prototype = false;

  /// Starts a part: the triangles added from now on carry (cls, material) until the next part.
  void beginPart(ClassId cls, MaterialId material);
  std::uint32_t addVertex(const Eigen::Vector3f& v) {
    vertices.push_back(v);
    return static_cast<std::uint32_t>(vertices.size() - 1);
  }
  void addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);
  /// Two triangles a b c, a c d.
  void addQuad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);
  std::size_t bytes() const;
};

/// Small closed shapes for prototypes and structures, in the current part of `mesh`.
/// A box from `lo` to `hi`.
void addBox(Mesh& mesh, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi);
/// A box given by its centre and three half-axes (any orientation).
void addOrientedBox(Mesh& mesh, const Eigen::Vector3f& centre, const Eigen::Vector3f& half_x,
                    const Eigen::Vector3f& half_y, const Eigen::Vector3f& half_z);
/// A capped cylinder (or cone, r_top != r_bottom) from `bottom` to `top` with `sides` sides.
void addCylinder(Mesh& mesh, const Eigen::Vector3f& bottom, const Eigen::Vector3f& top,
                 float r_bottom, float r_top, int sides);
/// A sphere-like closed blob: an icosphere subdivided `subdivisions` times, scaled by `radii`,
/// each vertex pushed out by radius·(1 + jitter[i]) (jitter indexed by vertex; empty = round).
void addBlob(Mesh& mesh, const Eigen::Vector3f& centre, const Eigen::Vector3f& radii,
             int subdivisions, std::span<const float> jitter = {});
/// The number of vertices addBlob makes for `subdivisions` (the size of its jitter).
std::size_t blobVertexCount(int subdivisions);

/// A polyline with a radius: contact and messenger wires, droppers. Kept as curves so the LiDAR
/// can intersect them as exact cylinders and the exporter can draw tubes; points relative to
/// the tile's origin.
struct Wire {
  std::vector<Eigen::Vector3f> points;
  float radius_m = 0.006f;
  ClassId cls = cls::kWire;
  MaterialId material = mat::kCopper;
  InstanceId instance = 0;
};

}  // namespace trainsim::scene
