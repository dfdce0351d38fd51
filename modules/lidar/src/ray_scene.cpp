// The Embree side of the LiDAR: tile and prototype BVHs, the per-frame top-level scene, and
// packet traversal. Embree 3.13 as Debian builds it: ray masks on (every ray sets mask = ~0),
// one instance level, TBB tasking (commits run in a build arena of their own, of fixed size).
#include "trainsim/lidar/ray_scene.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <pmmintrin.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <atomic>
#include <deque>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <string>

#include "embree_geometry.hpp"
#include "trainsim/core/error.hpp"

namespace trainsim::lidar {
namespace {

using detail::addGrid;
using detail::addTriangles;
using detail::addWire;
using detail::WireData;

std::mutex error_mutex;
std::string error_text;  // the device's last message, for the exception that reports it

void onEmbreeError(void* /*user*/, RTCError /*code*/, const char* message) {
  const std::lock_guard lock(error_mutex);
  error_text = message ? message : "";
}

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e == RTC_ERROR_NONE)
    return;
  const std::lock_guard lock(error_mutex);
  throw RuntimeError(
      fmt::format("Embree: {} failed (error {}: {})", what, static_cast<int>(e), error_text));
}

// Labels of one geometry of a BVH: a mesh's parts (class and material by triangle) or a wire's.
struct GeomInfo {
  const scene::Mesh* mesh = nullptr;  // null for a wire
  scene::ClassId cls = 0;
  scene::MaterialId material = 0;
  scene::InstanceId instance = 0;
};

struct SceneHandle {
  RTCScene scene = nullptr;
  SceneHandle() = default;
  explicit SceneHandle(RTCScene s) : scene(s) {}
  SceneHandle(const SceneHandle&) = delete;
  SceneHandle& operator=(const SceneHandle&) = delete;
  ~SceneHandle() {
    if (scene)
      rtcReleaseScene(scene);
  }
};

// Where the Earth's curvature tilts a tile's ground more than this against world axes (rad),
// the tile's BVH is built in its level axes (RayWorld's buildTile).
constexpr double kLevelTilt = 1e-3;

bool sharedMesh(const scene::Object& o) {
  return o.mesh->prototype;
}

// Threads a BVH build is cut up for, whatever the run has. Embree cuts each partition and
// reduction of a build into as many tasks as the calling TBB arena has threads, so the order
// primitives land in within the leaves can follow the thread count, and with it which of two
// triangles at the same distance (an edge) a ray returns. In an arena of a fixed size a BVH is
// the same on any machine and for any --threads.
constexpr int kBuildThreads = 2;

// Builds a scene's BVH in the world's build arena. The build runs under the world's lock; in
// that arena, waiting on the build, this thread can pick up only the build's own tasks, never
// another frame's that would ask for the lock again.
void commit(RTCScene scene, tbb::task_arena& arena) {
  arena.execute([&] { rtcCommitScene(scene); });
}

// A scene built once and cast into many times: high-quality BVH, robust traversal (no ray slips
// through an edge shared by two triangles, as terrain has everywhere).
RTCScene newStaticScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  return scene;
}

}  // namespace

// One tile's own geometry (terrain, rails, sleepers, ballast, structures, wires; with
// flattening also its objects), relative to the tile's origin.
struct TileBvh {
  std::shared_ptr<const scene::Tile> tile;
  std::vector<std::unique_ptr<WireData>> wires;         // the user geometries' data
  SceneHandle handle;                                   // released before the wires' data
  std::vector<GeomInfo> geoms;                          // by geomID
  Eigen::Matrix3f level = Eigen::Matrix3f::Identity();  // the BVH's axes to world axes
};

// A shared prototype's mesh, relative to its foot.
struct ProtoBvh {
  std::shared_ptr<const scene::Mesh> mesh;
  SceneHandle handle;
};

// One top-level instance: a tile or an object, held so that its BVH lives as long as the scene.
struct InstInfo {
  std::shared_ptr<const TileBvh> tile;    // set for a tile
  std::shared_ptr<const ProtoBvh> proto;  // set for an object
  scene::InstanceId instance = 0;
};

// What a hit needs of its instance, packed (the lookups of a hit's labels were chains of
// pointers into several structures, each a likely cache miss).
struct InstHit {
  Eigen::Matrix3f normal;          // inverse transpose of the linear part
  std::uint32_t first_object = 0;  // RayHit::object of its first geometry
  bool rotated = false;            // the linear part is not the identity
  bool tile = false;  // the geomID picks the object; otherwise the instance is one object
};

// An object's labels: its class and material, or (meshes of several parts) its parts to look
// the hit's triangle up in.
struct ObjectLabel {
  const scene::MeshPart* parts = nullptr;
  std::uint32_t part_count = 0;
  scene::ClassId cls = 0;
  scene::MaterialId material = 0;
};

struct RayScene::Impl {
  std::shared_ptr<void> device_keepalive;
  Eigen::Vector3d origin;
  SceneHandle top;
  std::vector<InstInfo> instances;         // by instID
  std::vector<InstHit> hits;               // by instID
  std::vector<ObjectLabel> labels;         // by RayHit::object
  std::vector<scene::InstanceId> objects;  // instance ids by RayHit::object
  std::vector<scene::TileIndex> key;
};

namespace {

void setFlushToZero() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

// RayPacket is Embree's RTCRayHit8 with the labels after it, filled and read in place.
static_assert(sizeof(RTCRayHit8) == offsetof(RayPacket, object) && offsetof(RTCRayHit8, ray) == 0 &&
              offsetof(RTCRayHit8, hit) == 12 * 32 &&
              offsetof(RayPacket, org_x) == offsetof(RTCRay8, org_x) &&
              offsetof(RayPacket, t_near) == offsetof(RTCRay8, tnear) &&
              offsetof(RayPacket, dir_x) == offsetof(RTCRay8, dir_x) &&
              offsetof(RayPacket, time) == offsetof(RTCRay8, time) &&
              offsetof(RayPacket, t_far) == offsetof(RTCRay8, tfar) &&
              offsetof(RayPacket, mask) == offsetof(RTCRay8, mask) &&
              offsetof(RayPacket, flags) == offsetof(RTCRay8, flags) &&
              offsetof(RayPacket, ng_x) == 12 * 32 + offsetof(RTCHit8, Ng_x) &&
              offsetof(RayPacket, prim) == 12 * 32 + offsetof(RTCHit8, primID) &&
              offsetof(RayPacket, geom) == 12 * 32 + offsetof(RTCHit8, geomID) &&
              offsetof(RayPacket, inst) == 12 * 32 + offsetof(RTCHit8, instID) &&
              RTC_MAX_INSTANCE_LEVEL_COUNT == 1 && alignof(RayPacket) >= alignof(RTCRayHit8));

RTCRayHit8& embree(RayPacket& p) {
  return *reinterpret_cast<RTCRayHit8*>(&p);
}

// Loads rays [first, first + n) of `rays` (n ≤ 8) into a packet; lanes past n are inactive.
void loadPacket(std::span<const Ray> rays, std::size_t first, std::size_t n, RayPacket& p,
                int valid[8]) {
  for (std::size_t k = 0; k < 8; ++k) {
    if (k >= n) {
      valid[k] = 0;
      continue;
    }
    const Ray& r = rays[first + k];
    valid[k] = -1;
    p.org_x[k] = r.origin.x();
    p.org_y[k] = r.origin.y();
    p.org_z[k] = r.origin.z();
    p.dir_x[k] = r.direction.x();
    p.dir_y[k] = r.direction.y();
    p.dir_z[k] = r.direction.z();
    p.t_near[k] = r.t_near;
    p.t_far[k] = r.t_far;
  }
}

// Casts a loaded packet: Embree's closest hits, no labels.
void castRaw(RTCScene scene, RTCIntersectContext& context, RayPacket& p, const int valid[8]) {
  std::fill_n(p.geom, 8, RTC_INVALID_GEOMETRY_ID);
  std::fill_n(p.inst, 8, RTC_INVALID_GEOMETRY_ID);
  rtcIntersect8(valid, scene, &context, &embree(p));
}

void coherentContext(RTCIntersectContext& context) {
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

// Casts `rays` in packets of 8 and hands each cast packet to `store(first, n, packet, valid)`:
// rays [first, first + n) in its first n lanes.
template <typename Store>
void castPackets(RTCScene scene, std::span<const Ray> rays, const Store& store) {
  setFlushToZero();
  RTCIntersectContext context;
  coherentContext(context);
  RayPacket packet;
  alignas(32) int valid[8];
  for (std::size_t first = 0; first < rays.size(); first += 8) {
    const std::size_t n = std::min<std::size_t>(8, rays.size() - first);
    loadPacket(rays, first, n, packet, valid);
    castRaw(scene, context, packet, valid);
    store(first, n, packet, valid);
  }
}

}  // namespace

RayPacket::RayPacket() {
  std::fill_n(time, 8, 0.0f);
  std::fill_n(mask, 8, 0xFFFFFFFFu);  // Debian's Embree has ray masks on
  std::iota(id, id + 8, 0u);
  std::fill_n(flags, 8, 0u);
}

const Eigen::Vector3d& RayScene::origin() const {
  return impl_->origin;
}

std::size_t RayScene::instanceCount() const {
  return impl_->instances.size();
}

const std::vector<scene::InstanceId>& RayScene::instances() const {
  return impl_->objects;
}

void RayScene::traverse(std::span<const Ray> rays, std::span<float> ranges, Traversal mode) const {
  RTCScene top = impl_->top.scene;
  if (mode == Traversal::kPacket8) {
    castPackets(top, rays, [&](std::size_t first, std::size_t n, const RayPacket& p, const int*) {
      for (std::size_t k = 0; k < n; ++k)
        ranges[first + k] = p.geom[k] == RTC_INVALID_GEOMETRY_ID
                                ? std::numeric_limits<float>::infinity()
                                : p.t_far[k];
    });
    return;
  }
  setFlushToZero();
  RTCIntersectContext context;
  coherentContext(context);
  std::vector<RTCRayHit> hits(mode == Traversal::kStream ? rays.size() : 1);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    RTCRayHit& h = hits[mode == Traversal::kStream ? i : 0];
    const Ray& r = rays[i];
    h.ray = {r.origin.x(),
             r.origin.y(),
             r.origin.z(),
             r.t_near,
             r.direction.x(),
             r.direction.y(),
             r.direction.z(),
             0.0f,
             r.t_far,
             0xFFFFFFFFu,
             0,
             0};
    h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    if (mode == Traversal::kSingle) {
      rtcIntersect1(top, &context, &h);
      ranges[i] = h.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity()
                                                          : h.ray.tfar;
    }
  }
  if (mode != Traversal::kStream)
    return;
  rtcIntersect1M(top, &context, hits.data(), static_cast<unsigned>(hits.size()), sizeof(RTCRayHit));
  for (std::size_t i = 0; i < rays.size(); ++i)
    ranges[i] = hits[i].hit.geomID == RTC_INVALID_GEOMETRY_ID
                    ? std::numeric_limits<float>::infinity()
                    : hits[i].ray.tfar;
}

namespace {

// Turns the hits of a cast packet into world normals and labels, lane by lane (inactive lanes
// come out as misses).
void label(const RayScene::Impl& s, RayPacket& p, const int valid[8]) {
  for (std::size_t k = 0; k < 8; ++k) {
    if (valid[k] == 0 || p.geom[k] == RTC_INVALID_GEOMETRY_ID) {
      p.t_far[k] = std::numeric_limits<float>::infinity();
      p.ng_x[k] = p.ng_y[k] = p.ng_z[k] = 0.0f;
      p.object[k] = 0;
      p.cls[k] = 0;
      p.material[k] = 0;
      continue;
    }
    const InstHit& inst = s.hits[p.inst[k]];
    if (inst.rotated) {  // Embree gives an instance's normal in the instance's own axes
      const Eigen::Vector3f n = inst.normal * Eigen::Vector3f(p.ng_x[k], p.ng_y[k], p.ng_z[k]);
      p.ng_x[k] = n.x();
      p.ng_y[k] = n.y();
      p.ng_z[k] = n.z();
    }
    const std::uint32_t object = inst.first_object + (inst.tile ? p.geom[k] : 0);
    p.object[k] = object;
    const ObjectLabel& label = s.labels[object];
    if (label.parts == nullptr) {
      p.cls[k] = label.cls;
      p.material[k] = label.material;
      continue;
    }
    const scene::MeshPart* part = std::prev(std::upper_bound(
        label.parts, label.parts + label.part_count, p.prim[k],
        [](unsigned t, const scene::MeshPart& q) { return t < q.first_triangle; }));
    p.cls[k] = part->cls;
    p.material[k] = part->material;
  }
}

}  // namespace

void RayScene::cast(std::span<RayPacket> packets, std::size_t rays) const {
  const Impl& s = *impl_;
  setFlushToZero();
  RTCIntersectContext context;
  coherentContext(context);
  alignas(32) int valid[8];
  std::fill_n(valid, 8, -1);
  for (std::size_t i = 0; i < packets.size() && 8 * i < rays; ++i) {
    for (std::size_t k = 0; k < 8; ++k)
      valid[k] = 8 * i + k < rays ? -1 : 0;
    castRaw(s.top.scene, context, packets[i], valid);
    label(s, packets[i], valid);
  }
}

void RayScene::intersect(std::span<const Ray> rays, std::span<RayHit> hits) const {
  const Impl& s = *impl_;
  castPackets(s.top.scene, rays,
              [&](std::size_t first, std::size_t n, RayPacket& p, const int* valid) {
                label(s, p, valid);
                for (std::size_t k = 0; k < n; ++k) {
                  RayHit& h = hits[first + k];
                  if (p.geom[k] == RTC_INVALID_GEOMETRY_ID) {
                    h = RayHit{};
                    continue;
                  }
                  const Eigen::Vector3f normal(p.ng_x[k], p.ng_y[k], p.ng_z[k]);
                  h.range = p.t_far[k];
                  h.normal = normal * (1.0f / normal.norm());  // one division, not three
                  h.object = p.object[k];
                  h.cls = p.cls[k];
                  h.material = p.material[k];
                }
              });
}

struct RayWorld::Impl {
  RayWorldOptions options;
  std::shared_ptr<RTCDeviceTy> device;
  std::atomic<std::int64_t> bytes{0};  // Embree's memory monitor
  std::mutex mutex;
  tbb::task_arena builds{kBuildThreads};  // every commit, under the lock
  std::map<scene::TileIndex, std::shared_ptr<const TileBvh>> tiles;
  std::deque<std::vector<scene::TileIndex>> recent;  // the tiles of the last scenes, newest last
  std::map<const scene::Mesh*, std::shared_ptr<const ProtoBvh>> protos;
  std::shared_ptr<const RayScene::Impl> last;
  // Scenes whose tiles keep their BVHs: more than the frames a run has in flight at once
  // (2 × threads + 1), so a tile is built once while the train passes it. Memory follows what
  // lies within reach, not the route; scenes still in use keep their own BVHs alive.
  static constexpr std::size_t kRecentScenes = 8;

  // Drops the BVHs of tiles in none of the recent scenes.
  void forget(const std::vector<scene::TileIndex>& key) {
    recent.push_back(key);
    if (recent.size() <= kRecentScenes)
      return;
    recent.pop_front();
    std::set<scene::TileIndex> keep;
    for (const auto& k : recent)
      keep.insert(k.begin(), k.end());
    std::erase_if(tiles, [&](const auto& entry) { return !keep.contains(entry.first); });
  }

  std::shared_ptr<const TileBvh> buildTile(const std::shared_ptr<const scene::Tile>& tile) {
    auto bvh = std::make_shared<TileBvh>();
    bvh->tile = tile;
    RTCDevice d = device.get();
    bvh->handle.scene = newStaticScene(d);
    // The BVH in axes whose z is the tile's up where the Earth's curvature tilts its ground more
    // than kLevelTilt against world axes (6.4 km from the scenario's origin): there Embree's
    // boxes around flat ground would be as thick as the tilt makes it (a frame 1000 km out took
    // 1.19 × the time). The least rotation that levels it: turning the axes about up as well
    // (the local east and north, some degrees off world x and y far out) would set the track
    // and the tile's own edges askew to the boxes. Nearer, world axes (no rotation, no normal
    // to turn back).
    const Eigen::Vector3d up = tile->level.col(2);
    const Eigen::Matrix3d to_level =
        std::acos(std::clamp(up.z(), -1.0, 1.0)) > kLevelTilt
            ? Eigen::Matrix3d(Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()))
            : Eigen::Matrix3d::Identity();
    const bool level = to_level.isIdentity(0.0);
    bvh->level = to_level.transpose().cast<float>();
    for (const scene::Object& o : tile->objects) {
      if (options.instance_objects && sharedMesh(o))
        continue;
      const Eigen::Vector3d offset = level ? Eigen::Vector3d(o.position - tile->origin)
                                           : to_level * (o.position - tile->origin);
      if (options.terrain_grids && o.mesh->grid_columns > 0 && o.linear.isIdentity(0.0f))
        addGrid(d, bvh->handle.scene, *o.mesh, offset, to_level);
      else
        addTriangles(d, bvh->handle.scene, *o.mesh, offset, o.linear, to_level);
      bvh->geoms.push_back({o.mesh.get(), 0, 0, o.instance});
    }
    for (const scene::Wire& w : tile->wires) {
      if (w.points.size() < 2)
        continue;
      bvh->wires.push_back(std::make_unique<WireData>());
      addWire(d, bvh->handle.scene, w, to_level, *bvh->wires.back());
      bvh->geoms.push_back({nullptr, w.cls, w.material, w.instance});
    }
    commit(bvh->handle.scene, builds);
    check(d, "building a tile's BVH");
    return bvh;
  }

  std::shared_ptr<const TileBvh> tile(const std::shared_ptr<const scene::Tile>& t) {
    if (auto it = tiles.find(t->index); it != tiles.end())
      return it->second;
    auto bvh = buildTile(t);
    tiles.emplace(t->index, bvh);
    return bvh;
  }

  std::shared_ptr<const ProtoBvh> proto(const std::shared_ptr<const scene::Mesh>& mesh) {
    auto it = protos.find(mesh.get());
    if (it != protos.end())
      return it->second;
    auto bvh = std::make_shared<ProtoBvh>();
    bvh->mesh = mesh;
    RTCDevice d = device.get();
    bvh->handle.scene = newStaticScene(d);
    addTriangles(d, bvh->handle.scene, *mesh, Eigen::Vector3d::Zero(), Eigen::Matrix3f::Identity());
    commit(bvh->handle.scene, builds);
    check(d, "building a prototype's BVH");
    protos.emplace(mesh.get(), bvh);
    return bvh;
  }
};

RayWorld::RayWorld(RayWorldOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  // Embree picks its kernels by the CPU, and each ISA rounds differently in the last bit of a
  // float: capping the ISA makes the bytes the same on every machine that has it.
  const std::string config = "max_isa=" + options.max_isa;
  RTCDevice device = rtcNewDevice(config.c_str());
  if (device == nullptr)
    throw RuntimeError(fmt::format("Embree: cannot create a device (error {})",
                                   static_cast<int>(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(device, &onEmbreeError, nullptr);
  rtcSetDeviceMemoryMonitorFunction(
      device,
      [](void* user, ssize_t bytes, bool /*post*/) {
        static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes);
        return true;
      },
      &impl_->bytes);
  impl_->device = std::shared_ptr<RTCDeviceTy>(device, [](RTCDevice d) { rtcReleaseDevice(d); });
}

RayWorld::~RayWorld() = default;

std::int64_t RayWorld::bytes() const {
  return impl_->bytes.load();
}

RayScene RayWorld::scene(const std::vector<std::shared_ptr<const scene::Tile>>& tiles) {
  Impl& w = *impl_;
  const std::lock_guard lock(w.mutex);
  std::vector<scene::TileIndex> key;
  for (const auto& t : tiles)
    key.push_back(t->index);
  if (w.last && w.last->key == key)
    return RayScene(w.last);
  auto s = std::make_shared<RayScene::Impl>();
  s->device_keepalive = w.device;
  s->key = key;
  s->origin = tiles.empty() ? Eigen::Vector3d::Zero() : tiles.front()->origin;
  RTCDevice d = w.device.get();
  s->top.scene = rtcNewScene(d);
  rtcSetSceneFlags(s->top.scene, RTC_SCENE_FLAG_ROBUST);
  const auto attach = [&](RTCScene child, const Eigen::Matrix3f& linear,
                          const Eigen::Vector3d& position, InstInfo info) {
    RTCGeometry g = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, child);
    const Eigen::Vector3d t = position - s->origin;  // in double, then float
    float xfm[12];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        xfm[4 * r + c] = linear(r, c);
      xfm[4 * r + 3] = static_cast<float>(t[r]);
    }
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
    rtcCommitGeometry(g);
    rtcAttachGeometry(s->top.scene, g);
    rtcReleaseGeometry(g);
    const auto first_object = static_cast<std::uint32_t>(s->objects.size());
    const auto label = [](const GeomInfo& geom) {
      if (geom.mesh == nullptr)
        return ObjectLabel{nullptr, 0, geom.cls, geom.material};
      const auto& parts = geom.mesh->parts;
      if (parts.size() == 1)
        return ObjectLabel{nullptr, 0, parts[0].cls, parts[0].material};
      return ObjectLabel{parts.data(), static_cast<std::uint32_t>(parts.size()), 0, 0};
    };
    if (info.proto) {
      s->objects.push_back(info.instance);
      s->labels.push_back(label({info.proto->mesh.get(), 0, 0, info.instance}));
    } else {
      for (const GeomInfo& geom : info.tile->geoms) {
        s->objects.push_back(geom.instance);
        s->labels.push_back(label(geom));
      }
    }
    s->hits.push_back({linear.inverse().transpose(), first_object, !linear.isIdentity(0.0f),
                       info.tile != nullptr});
    s->instances.push_back(std::move(info));
  };
  for (const auto& t : tiles) {
    auto bvh = w.tile(t);
    attach(bvh->handle.scene, bvh->level, t->origin, {bvh, nullptr, 0});
    if (!w.options.instance_objects)
      continue;
    for (const scene::Object& o : t->objects)
      if (sharedMesh(o)) {
        auto proto = w.proto(o.mesh);
        attach(proto->handle.scene, o.linear, o.position, {nullptr, proto, o.instance});
      }
  }
  commit(s->top.scene, w.builds);
  check(d, "building the frame's top-level scene");
  w.last = s;
  w.forget(key);
  return RayScene(std::move(s));
}

}  // namespace trainsim::lidar
