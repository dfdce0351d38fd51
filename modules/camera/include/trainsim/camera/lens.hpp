#pragma once
// Lens distortion: a distorted camera's images made from a pinhole render by OpenCV's remap.
#include <memory>
#include <string>

#include <Eigen/Core>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/camera/renderer.hpp"

namespace trainsim::camera {

/// Brown–Conrady distortion as OpenCV models it: for a point (x, y) = (X/Z, Y/Z) of the pinhole
/// and r² = x² + y², the lens images it at
///   x' = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2 x²),
///   y' = y (1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2 y²) + 2 p2 x y,
/// and the pixel is (fx x' + cx, fy y' + cy).
struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;

  bool none() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
  /// (x', y') of (x, y).
  Eigen::Vector2d apply(const Eigen::Vector2d& xy) const;
};

/// Why `d` cannot serve a camera with intrinsics `k` (its inversion fails on the image's rim,
/// where the distortion folds first), or empty: a cheap check for validation, where LensRemap
/// checks every pixel.
std::string lensProblem(const Intrinsics& k, const Distortion& d);

/// The images of a distorted camera with intrinsics K (output size) made from a pinhole render:
/// the render has the same optical centre and axes, covers every ray of the distorted image and
/// has at least one pixel per output pixel everywhere; each output pixel then takes the render
/// at the point its ray passes through (cv::remap; bilinear for colour, nearest for depth and
/// ids so that no depth or label is blended across an edge). Depth along the optical axis is
/// the same in both, so it is carried over as it is.
class LensRemap {
 public:
  LensRemap(const Intrinsics& output, const Distortion& distortion);
  ~LensRemap();
  LensRemap(const LensRemap&) = delete;
  LensRemap& operator=(const LensRemap&) = delete;

  /// The pinhole camera to render with.
  const Intrinsics& render() const { return render_; }
  /// The output images of a render made with render().
  CameraImages apply(const CameraImages& rendered) const;

 private:
  struct Maps;
  Intrinsics output_, render_;
  std::unique_ptr<Maps> maps_;
};

}  // namespace trainsim::camera
