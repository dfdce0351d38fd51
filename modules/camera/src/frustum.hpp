#pragma once
// Private to the camera module: what of the scene a camera can see.
#include <array>

#include <Eigen/Geometry>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim::camera {

// The view frustum in the camera frame: a box is outside if all its corners lie beyond one of
// the four side planes, before the near plane or past the far plane.
class Frustum {
 public:
  Frustum(const Intrinsics& k, double near_m, double far_m, const Eigen::Isometry3d& T_cam_world)
      : T_cam_world_(T_cam_world), near_(near_m), far_(far_m) {
    // u ≥ −0.5: fx x + (cx + 0.5) z ≥ 0; u ≤ W − 0.5: −fx x + (W − 0.5 − cx) z ≥ 0; same in v.
    planes_[0] = {k.fx, 0.0, k.cx + 0.5};
    planes_[1] = {-k.fx, 0.0, k.width - 0.5 - k.cx};
    planes_[2] = {0.0, k.fy, k.cy + 0.5};
    planes_[3] = {0.0, -k.fy, k.height - 0.5 - k.cy};
  }

  // Whether the box (world) may show: false only where it is wholly outside.
  bool meets(const scene::Box3d& box) const;

 private:
  Eigen::Isometry3d T_cam_world_;
  double near_, far_;
  std::array<Eigen::Vector3d, 4> planes_;
};

}  // namespace trainsim::camera
