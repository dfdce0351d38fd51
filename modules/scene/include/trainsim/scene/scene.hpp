#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include <Eigen/Core>

#include "trainsim/scene/mesh.hpp"

namespace trainsim::scene {

/// An object of the scene: a shared mesh placed in the world. World position in double; the
/// mesh's float vertices are relative to it, turned (and scaled) by `linear`. Class and
/// material come from the mesh's parts; the instance id is the object's.
struct Object {
  std::shared_ptr<const Mesh> mesh;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3f linear = Eigen::Matrix3f::Identity();
  InstanceId instance = 0;
  Box3d bounds;  ///< world box, set by place()

  /// An object with its world box computed (once: the box is kept).
  static Object place(std::shared_ptr<const Mesh> mesh, const Eigen::Vector3d& position,
                      const Eigen::Matrix3f& linear, InstanceId instance);

  /// A vertex of the mesh in world coordinates (double).
  Eigen::Vector3d worldVertex(std::uint32_t i) const {
    return position + (linear * mesh->vertices[i]).cast<double>();
  }
};

/// A tile of the world: a square of the terrain grid with everything whose anchor lies in it.
/// (i, j) index the squares of side TileGrid::size_m from the world origin.
struct TileIndex {
  std::int32_t i = 0, j = 0;
  auto operator<=>(const TileIndex&) const = default;
};

struct Tile {
  TileIndex index;
  /// The tile's local origin (world, double): meshes owned by the tile (terrain, rails, ballast)
  /// and its wires hold float vertices relative to it, so they stay accurate to well under a
  /// millimetre however far the tile is from the scenario origin.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Object> objects;
  std::vector<Wire> wires;
  Box3d bounds;  ///< world box of everything in the tile (objects and wires)
  /// Rotation from the level frame at the tile's origin (east, north and up of the ellipsoid
  /// there) to world axes: the identity at the scenario's origin. The tile's geometry is in
  /// world axes, the anchor's tangent plane, against which the ground far out is tilted by the
  /// Earth's curvature (0.9° at 100 km, 9° at 1000 km); a ray caster builds its acceleration
  /// structure in these axes instead, where the ground is level and boxes around it thin.
  Eigen::Matrix3d level = Eigen::Matrix3d::Identity();

  /// Recomputes `bounds` from the objects and wires.
  void updateBounds();
  /// Bytes the tile owns: its objects, wires and the meshes only it uses (shared prototypes are
  /// counted by whoever owns them).
  std::size_t bytes() const;
  std::size_t triangleCount() const;
};

/// The square tiling of the plane: tile (i, j) covers [i·size, (i+1)·size) × [j·size, (j+1)·size).
struct TileGrid {
  double size_m = 1008.0;
  TileIndex tileAt(double x, double y) const;
  Eigen::Vector2d corner(TileIndex t) const { return {t.i * size_m, t.j * size_m}; }
  /// Plan distance from (x, y) to the tile's square, 0 inside.
  double distance(TileIndex t, const Eigen::Vector2d& p) const;
};

/// Makes a tile: must be a pure function of the index (the same bytes in any order, on any
/// thread), and thread-safe.
using TileFactory = std::function<std::shared_ptr<const Tile>(TileIndex)>;

/// The tiles within reach of a pose, for one sensor frame.
struct SceneWindow {
  std::vector<std::shared_ptr<const Tile>> tiles;  ///< ordered by index
  /// Calls visit(object) for every object whose world box comes within `radius` (plan) of
  /// `centre`.
  void forEachObject(const Eigen::Vector3d& centre, double radius,
                     const std::function<void(const Object&)>& visit) const;
};

/// The scene as it streams along the route: the set of tiles that exist (fixed by the plan),
/// made on demand by the factory and dropped least-recently-used beyond `capacity` (or twice
/// the tiles the largest window so far looked at, if more), so memory and the cost of a query
/// do not grow with the route. Thread-safe; a tile is made once even if several threads ask for
/// it at the same time.
class SceneStream {
 public:
  /// `overhang_m`: how far (plan) a tile's content can reach beyond its square (an object
  /// belongs to one tile, and a catenary span or a house reaches into the next).
  SceneStream(TileGrid grid, std::set<TileIndex> existing, TileFactory factory,
              std::size_t capacity = 16, double overhang_m = 0.0);

  /// Every existing tile whose content (Tile::bounds) comes within `radius` (plan) of
  /// `centre`: the tiles whose square does, and those within the overhang whose content
  /// reaches in.
  SceneWindow window(const Eigen::Vector3d& centre, double radius);
  /// One tile (made if needed); nullptr if it does not exist.
  std::shared_ptr<const Tile> tile(TileIndex index);

  const TileGrid& grid() const { return grid_; }
  /// Tiles held now, tiles made so far (a dropped tile asked for again is made again).
  std::size_t cached() const;
  std::int64_t made() const;
  /// Bytes the held tiles own (Tile::bytes), the scene's share of memory.
  std::size_t bytes() const;

 private:
  struct Slot {
    std::shared_future<std::shared_ptr<const Tile>> tile;
    std::list<TileIndex>::iterator lru;
  };
  TileGrid grid_;
  std::set<TileIndex> existing_;
  TileFactory factory_;
  std::size_t capacity_;
  double overhang_m_;
  mutable std::mutex mutex_;
  std::map<TileIndex, Slot> cache_;
  std::list<TileIndex> lru_;  ///< most recent first
  std::int64_t made_ = 0;
};

}  // namespace trainsim::scene
