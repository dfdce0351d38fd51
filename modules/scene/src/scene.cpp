#include "trainsim/scene/scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace trainsim::scene {

Object Object::place(std::shared_ptr<const Mesh> mesh, const Eigen::Vector3d& position,
                     const Eigen::Matrix3f& linear, InstanceId instance) {
  Object object{std::move(mesh), position, linear, instance, {}};
  // The mesh's box through the linear map: the box of its eight corners bounds the object.
  Box3d local;
  for (const auto& v : object.mesh->vertices)
    local.extend(v.cast<double>());
  if (local.empty())
    return object;
  const Eigen::Matrix3d m = linear.cast<double>();
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c((corner & 1) ? local.max.x() : local.min.x(),
                            (corner & 2) ? local.max.y() : local.min.y(),
                            (corner & 4) ? local.max.z() : local.min.z());
    object.bounds.extend(position + m * c);
  }
  return object;
}

void Tile::updateBounds() {
  bounds = Box3d{};
  for (const auto& object : objects)
    bounds.extend(object.bounds);
  for (const auto& wire : wires)
    for (const auto& p : wire.points) {
      const Eigen::Vector3d w = origin + p.cast<double>();
      bounds.extend(w - Eigen::Vector3d::Constant(wire.radius_m));
      bounds.extend(w + Eigen::Vector3d::Constant(wire.radius_m));
    }
}

std::size_t Tile::bytes() const {
  std::size_t total =
      sizeof(Tile) + objects.capacity() * sizeof(Object) + wires.capacity() * sizeof(Wire);
  for (const auto& wire : wires)
    total += wire.points.capacity() * sizeof(Eigen::Vector3f);
  // A mesh that is not a shared prototype (its terrain, rails, ballast) belongs to the tile.
  for (const auto& object : objects)
    if (!object.mesh->prototype)
      total += object.mesh->bytes();
  return total;
}

std::size_t Tile::triangleCount() const {
  std::size_t n = 0;
  for (const auto& object : objects)
    n += object.mesh->triangles.size();
  return n;
}

TileIndex TileGrid::tileAt(double x, double y) const {
  return {static_cast<std::int32_t>(std::floor(x / size_m)),
          static_cast<std::int32_t>(std::floor(y / size_m))};
}

double TileGrid::distance(TileIndex t, const Eigen::Vector2d& p) const {
  const Eigen::Vector2d lo = corner(t);
  const double dx = std::max({lo.x() - p.x(), 0.0, p.x() - (lo.x() + size_m)});
  const double dy = std::max({lo.y() - p.y(), 0.0, p.y() - (lo.y() + size_m)});
  return std::hypot(dx, dy);
}

void SceneWindow::forEachObject(const Eigen::Vector3d& centre, double radius,
                                const std::function<void(const Object&)>& visit) const {
  const Eigen::Vector2d c = centre.head<2>();
  for (const auto& tile : tiles) {
    if (tile->bounds.planDistance(c) > radius)
      continue;
    for (const auto& object : tile->objects)
      if (object.bounds.planDistance(c) <= radius)
        visit(object);
  }
}

SceneStream::SceneStream(TileGrid grid, std::set<TileIndex> existing, TileFactory factory,
                         std::size_t capacity, double overhang_m)
    : grid_(grid),
      existing_(std::move(existing)),
      factory_(std::move(factory)),
      capacity_(std::max<std::size_t>(capacity, 1)),
      overhang_m_(overhang_m) {}

std::shared_ptr<const Tile> SceneStream::tile(TileIndex index) {
  if (!existing_.contains(index))
    return nullptr;
  std::shared_future<std::shared_ptr<const Tile>> future;
  std::promise<std::shared_ptr<const Tile>> promise;
  bool make = false;
  {
    std::lock_guard lock(mutex_);
    auto it = cache_.find(index);
    if (it != cache_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second.lru);
      future = it->second.tile;
    } else {
      future = promise.get_future().share();
      lru_.push_front(index);
      cache_.emplace(index, Slot{future, lru_.begin()});
      ++made_;
      make = true;
      while (cache_.size() > capacity_) {  // drop the least recently used (never this one)
        cache_.erase(lru_.back());
        lru_.pop_back();
      }
    }
  }
  if (make) {
    // Made outside the lock, so other tiles can be made or read meanwhile; a thread asking for
    // this tile now waits on the same future.
    try {
      promise.set_value(factory_(index));
    } catch (...) {
      {
        std::lock_guard lock(mutex_);
        if (auto it = cache_.find(index); it != cache_.end()) {
          lru_.erase(it->second.lru);
          cache_.erase(it);
        }
      }
      promise.set_exception(std::current_exception());
    }
  }
  return future.get();
}

SceneWindow SceneStream::window(const Eigen::Vector3d& centre, double radius) {
  SceneWindow window;
  const Eigen::Vector2d c = centre.head<2>();
  const double reach = radius + overhang_m_;
  const TileIndex lo = grid_.tileAt(c.x() - reach, c.y() - reach);
  const TileIndex hi = grid_.tileAt(c.x() + reach, c.y() + reach);
  std::vector<TileIndex> candidates;
  for (std::int32_t i = lo.i; i <= hi.i; ++i)
    for (std::int32_t j = lo.j; j <= hi.j; ++j)
      if (const TileIndex t{i, j}; existing_.contains(t) && grid_.distance(t, c) <= reach)
        candidates.push_back(t);
  {
    // Room for this window's tiles and the next one's, which mostly overlap: frames in flight
    // would otherwise drop each other's tiles and make them again.
    std::lock_guard lock(mutex_);
    capacity_ = std::max(capacity_, 2 * candidates.size());
  }
  for (const TileIndex t : candidates) {
    std::shared_ptr<const Tile> made = tile(t);
    if (grid_.distance(t, c) <= radius || made->bounds.planDistance(c) <= radius)
      window.tiles.push_back(std::move(made));
  }
  return window;
}

std::size_t SceneStream::cached() const {
  std::lock_guard lock(mutex_);
  return cache_.size();
}
std::size_t SceneStream::bytes() const {
  std::lock_guard lock(mutex_);
  std::size_t total = 0;
  for (const auto& [index, slot] : cache_)
    if (slot.tile.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
      if (const auto tile = slot.tile.get())
        total += tile->bytes();
  return total;
}

std::int64_t SceneStream::made() const {
  std::lock_guard lock(mutex_);
  return made_;
}

}  // namespace trainsim::scene
