#include "frustum.hpp"

#include <algorithm>

namespace trainsim::camera {

bool Frustum::meets(const scene::Box3d& box) const {
  if (box.empty())
    return false;
  std::array<Eigen::Vector3d, 8> c;
  for (int i = 0; i < 8; ++i)
    c[i] = T_cam_world_ * Eigen::Vector3d(i & 1 ? box.max.x() : box.min.x(),
                                          i & 2 ? box.max.y() : box.min.y(),
                                          i & 4 ? box.max.z() : box.min.z());
  const auto all = [&](auto outside) { return std::all_of(c.begin(), c.end(), outside); };
  if (all([&](const Eigen::Vector3d& p) { return p.z() < near_; }) ||
      all([&](const Eigen::Vector3d& p) { return p.z() > far_; }))
    return false;
  for (const Eigen::Vector3d& n : planes_)
    if (all([&](const Eigen::Vector3d& p) { return n.dot(p) < 0.0; }))
      return false;
  return true;
}

}  // namespace trainsim::camera
