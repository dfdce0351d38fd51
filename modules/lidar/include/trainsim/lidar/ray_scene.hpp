#pragma once
// Ray casting against the streamed scene with Embree, behind a pimpl: no Embree type here.
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "trainsim/scene/scene.hpp"

namespace trainsim::lidar {

/// A ray relative to its scene's origin (float is enough there: the origin is near the
/// sensor). `direction` must be a unit vector, so hit distances are ranges.
struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();
  float t_near = 0.0f;
  float t_far = std::numeric_limits<float>::infinity();
};

/// What a ray hit: range (infinity for a miss), the unit geometric normal in world axes
/// (facing either way), and the labels of the surface: its class, material and object (an
/// index into RayScene::instances(), whose instance id it has).
struct RayHit {
  float range = std::numeric_limits<float>::infinity();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  scene::ClassId cls = 0;
  scene::MaterialId material = 0;
  std::uint32_t object = 0;
  bool hit() const { return range < std::numeric_limits<float>::infinity(); }
};

/// Eight rays cast together, laid out as Embree's packet of eight (RTCRayHit8, checked where
/// Embree is included): the scanner fills the rays in place and reads the hits in place, so
/// nothing is copied on the way to Embree and back. A new packet has every ray's constant
/// fields set; the caller sets origins (relative to the scene's origin), unit directions and
/// each ray's [t_near, t_far].
struct alignas(32) RayPacket {
  float org_x[8], org_y[8], org_z[8], t_near[8], dir_x[8], dir_y[8], dir_z[8], time[8], t_far[8];
  std::uint32_t mask[8], id[8], flags[8];
  /// After RayScene::cast, per lane: t_far the hit's range (infinity for a miss) and the
  /// geometric normal in world axes, facing either way and not of unit length (0 for a miss).
  float ng_x[8], ng_y[8], ng_z[8], u[8], v[8];
  std::uint32_t prim[8], geom[8], inst[8];
  /// After RayScene::cast, per lane: the labels of the surface hit (RayHit's; 0 for a miss).
  std::uint32_t object[8];
  scene::ClassId cls[8];
  scene::MaterialId material[8];

  RayPacket();
};

/// The scene a frame's rays are cast against: the tiles within the sensor's reach, each tile's
/// own geometry one BVH (built once per tile and instanced), shared prototypes (trees, rocks,
/// signals) one BVH each, instanced per object, wires as exact capsules (a user geometry
/// intersected in double). Everything is
/// placed relative to origin() in float, transforms computed in double, so accuracy does not
/// depend on the distance from the scenario origin. Immutable, thread-safe to cast into.
class RayScene {
 public:
  /// The scene's origin (world, double): ray origins are relative to it.
  const Eigen::Vector3d& origin() const;
  /// Casts `rays` in packets of 8 (coherent: keep them in scan order) and writes `hits`.
  /// Sets flush-to-zero and denormals-are-zero on the calling thread.
  void intersect(std::span<const Ray> rays, std::span<RayHit> hits) const;
  /// Casts the first `rays` rays of `packets` (eight a packet; the lanes past them are not
  /// cast, and come out as misses) and writes their hits and labels into the packets (see
  /// RayPacket). Sets
  /// flush-to-zero and denormals-are-zero on the calling thread.
  void cast(std::span<RayPacket> packets, std::size_t rays) const;
  /// Top-level instances (tiles + instanced objects).
  std::size_t instanceCount() const;
  /// The instance ids of the scene's objects (every geometry of a tile, every instanced
  /// object), by RayHit::object; 0 for "stuff" without instances.
  const std::vector<scene::InstanceId>& instances() const;

  /// How the benchmark's raw traversal hands rays to Embree.
  enum class Traversal { kPacket8, kSingle, kStream };
  /// The raw traversal: Embree's closest hits of `rays`, ranges only (infinity for a miss), no
  /// labels, no normals: the baseline a frame's cost is measured against (bench_lidar).
  void traverse(std::span<const Ray> rays, std::span<float> ranges,
                Traversal mode = Traversal::kPacket8) const;

  struct Impl;

 private:
  friend class RayWorld;
  explicit RayScene(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

struct RayWorldOptions {
  /// Shared prototypes as Embree instances (stored once); false bakes every object's triangles
  /// into its tile's BVH (the benchmark's "flattened" comparison).
  bool instance_objects = true;
  /// The widest instruction set Embree may use. Each ISA rounds the last bit of a float its own
  /// way, so the default, AVX2 (every x86-64 CPU since 2015), gives the same bytes on every
  /// machine that has it, AVX-512 ones included; "avx512" is for the benchmark's comparison.
  std::string max_isa = "avx2";
  /// Height fields (scene::Mesh::grid_columns: the full-resolution terrain) as Embree grid
  /// geometry, which stores only the vertices, instead of triangles; the same surface.
  bool terrain_grids = false;
};

/// The Embree device and the BVHs built so far: one per tile (kept while the tile is in one of
/// the last scenes asked for) and one per shared prototype. A run makes one and asks it for a
/// scene per frame; a frame whose tiles are those of the previous frame gets the same scene.
/// Thread-safe.
class RayWorld {
 public:
  explicit RayWorld(RayWorldOptions options = {});
  ~RayWorld();
  RayWorld(const RayWorld&) = delete;
  RayWorld& operator=(const RayWorld&) = delete;

  /// The scene of these tiles (a window of the scene stream), origin at the first tile's
  /// origin: a pure function of the tiles, so frames cast the same bytes whichever thread or
  /// order made the scene.
  RayScene scene(const std::vector<std::shared_ptr<const scene::Tile>>& tiles);
  /// Bytes Embree holds now (its memory monitor): the BVHs and geometry buffers.
  std::int64_t bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trainsim::lidar
