#pragma once
// A pinhole camera in OpenCV's and KITTI's conventions: camera axes x right, y down, z forward
// (along the optical axis); pixel (u, v) with u to the right, v down, integer values at pixel
// centres, (0, 0) the centre of the top-left pixel.
#include <Eigen/Core>

namespace trainsim::camera {

struct Intrinsics {
  int width = 1242, height = 375;
  double fx = 0.0, fy = 0.0;  ///< focal lengths, pixels
  double cx = 0.0, cy = 0.0;  ///< principal point, pixels

  /// Square pixels with the principal point at the image centre and the given horizontal field
  /// of view (full angle, radians).
  static Intrinsics fromHorizontalFov(int width, int height, double hfov_rad);
  /// K, the 3 × 3 camera matrix.
  Eigen::Matrix3d matrix() const;
  /// The pixel a point in the camera frame projects to (z > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const {
    return {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  }
  /// How far a ray reaches for one metre of depth, at its longest: √(1 + x² + y²) at the
  /// image's farthest corner (pixel edges, x = (u − cx) / fx, y likewise). Whatever lies within
  /// a depth d of the camera lies within d times this of it.
  double farthestRay() const;
  /// The most a ray strays sideways for one metre of depth: |x| at the image's left or right
  /// edge.
  double widestSideways() const;
  /// The OpenGL projection (view → clip, OpenGL's eye axes: x right, y up, looking down −z)
  /// whose image is exactly this camera's at width × height pixels, with depth mapped from
  /// [near, far] to OpenGL's [−1, 1]: a point projects to the centre of pixel (u, v) as
  /// project() gives it.
  Eigen::Matrix4d glProjection(double near_m, double far_m) const;
};

/// Metric depth along the optical axis from an OpenGL depth-buffer value d ∈ [0, 1] of a
/// glProjection(near, far) render: n f / (f − d (f − n)); d = 1 is the far plane (nothing).
double depthFromBuffer(double d, double near_m, double far_m);

}  // namespace trainsim::camera
