#include "trainsim/camera/camera_model.hpp"

#include <algorithm>
#include <cmath>

namespace trainsim::camera {

Intrinsics Intrinsics::fromHorizontalFov(int width, int height, double hfov_rad) {
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width / std::tan(0.5 * hfov_rad);
  // The image's centre in pixel-centre coordinates: between the middle two pixels of an even
  // width.
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

Eigen::Matrix3d Intrinsics::matrix() const {
  Eigen::Matrix3d K;
  K << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return K;
}

double Intrinsics::widestSideways() const {
  return std::max(std::abs(-0.5 - cx), std::abs(width - 0.5 - cx)) / fx;
}

double Intrinsics::farthestRay() const {
  const double y = std::max(std::abs(-0.5 - cy), std::abs(height - 0.5 - cy)) / fy;
  const double x = widestSideways();
  return std::sqrt(1.0 + x * x + y * y);
}

Eigen::Matrix4d Intrinsics::glProjection(double n, double f) const {
  // OpenGL eye axes against the camera's: x_e = x, y_e = −y, z_e = −z. Pixel u's centre lies at
  // window x = u + 0.5, so x_ndc = 2 (u + 0.5) / W − 1 with u = fx x / z + cx; window y counts
  // up from the bottom row, so y_ndc = 1 − 2 (v + 0.5) / H. Multiplying through by w = −z_e
  // gives the rows below.
  const double W = width, H = height;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2.0 * fx / W;
  P(0, 2) = 1.0 - 2.0 * (cx + 0.5) / W;
  P(1, 1) = 2.0 * fy / H;
  P(1, 2) = 2.0 * (cy + 0.5) / H - 1.0;
  P(2, 2) = -(f + n) / (f - n);
  P(2, 3) = -2.0 * f * n / (f - n);
  P(3, 2) = -1.0;
  return P;
}

double depthFromBuffer(double d, double n, double f) {
  return n * f / (f - d * (f - n));
}

}  // namespace trainsim::camera
