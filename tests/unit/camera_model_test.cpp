// The pinhole model's OpenGL projection against its own pixel projection, without rendering.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/camera/exposure.hpp"
#include "trainsim/camera/lens.hpp"

namespace trainsim {
namespace {

using camera::Intrinsics;

// Where OpenGL puts a camera-frame point: clip = P · eye, window = (ndc + 1) / 2 · size, and the
// pixel-centre coordinate is window − 0.5 (rows counted from the top).
Eigen::Vector3d glPixel(const Intrinsics& k, const Eigen::Matrix4d& P, const Eigen::Vector3d& p) {
  const Eigen::Vector4d eye(p.x(), -p.y(), -p.z(), 1.0);
  const Eigen::Vector4d clip = P * eye;
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  const double wx = (ndc.x() + 1.0) / 2.0 * k.width, wy = (ndc.y() + 1.0) / 2.0 * k.height;
  return {wx - 0.5, k.height - wy - 0.5, (ndc.z() + 1.0) / 2.0};
}

TEST(CameraModel, TheOpenGlProjectionLandsWhereThePinholeDoes) {
  Intrinsics k;
  k.width = 1242;
  k.height = 375;
  k.fx = 718.856;
  k.fy = 712.0;  // not square, and the principal point off centre
  k.cx = 607.19;
  k.cy = 185.22;
  const double n = 0.5, f = 400.0;
  const Eigen::Matrix4d P = k.glProjection(n, f);
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.0, 0.0, 10.0), Eigen::Vector3d(-3.0, 1.2, 7.5),
        Eigen::Vector3d(40.0, -8.0, 90.0), Eigen::Vector3d(-0.2, 0.1, 0.6)}) {
    const Eigen::Vector3d g = glPixel(k, P, p);
    const Eigen::Vector2d uv = k.project(p);
    EXPECT_NEAR(g.x(), uv.x(), 1e-9);
    EXPECT_NEAR(g.y(), uv.y(), 1e-9);
    // The depth buffer's value maps back to the point's depth.
    EXPECT_NEAR(camera::depthFromBuffer(g.z(), n, f), p.z(), 1e-9 * p.z());
  }
  EXPECT_NEAR(camera::depthFromBuffer(0.0, n, f), n, 1e-12);
  EXPECT_NEAR(camera::depthFromBuffer(1.0, n, f), f, 1e-9);
}

TEST(CameraModel, AHorizontalFieldOfViewGivesSquarePixelsCentred) {
  const Intrinsics k = Intrinsics::fromHorizontalFov(1242, 375, 90.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(k.fx, 621.0);
  EXPECT_DOUBLE_EQ(k.fy, 621.0);
  // The image's edges (pixel borders at −0.5 and W − 0.5) at ±45°.
  EXPECT_NEAR(k.project({-1.0, 0.0, 1.0}).x(), -0.5, 1e-12);
  EXPECT_NEAR(k.project({1.0, 0.0, 1.0}).x(), 1241.5, 1e-12);
  EXPECT_NEAR(k.project({0.0, 0.0, 1.0}).y(), 187.0, 1e-12);
}

TEST(CameraModel, TheFarthestRayIsThatOfThePicturesFarthestCorner) {
  // A camera's scene window reaches the far plane at the farthest corner: the longest ray a
  // pixel's area holds for one metre of depth, against every pixel border, for an off-centre
  // principal point and fx ≠ fy; and the most a ray strays sideways.
  const Intrinsics k{
      .width = 320, .height = 240, .fx = 300.0, .fy = 280.0, .cx = 150.3, .cy = 131.7};
  double longest = 0.0, widest = 0.0;
  for (int v = 0; v <= k.height; ++v)
    for (int u = 0; u <= k.width; ++u) {
      const double x = (u - 0.5 - k.cx) / k.fx, y = (v - 0.5 - k.cy) / k.fy;
      longest = std::max(longest, std::sqrt(1.0 + x * x + y * y));
      widest = std::max(widest, std::abs(x));
    }
  EXPECT_NEAR(k.farthestRay(), longest, 1e-12);
  EXPECT_NEAR(k.widestSideways(), widest, 1e-12);
  // The default camera (81.6 deg across, 1242 x 375): 1.35 times its draw distance.
  const Intrinsics d = Intrinsics::fromHorizontalFov(1242, 375, 81.6 * std::numbers::pi / 180.0);
  EXPECT_NEAR(d.farthestRay(), 1.347, 1e-3);
}

}  // namespace
}  // namespace trainsim

namespace trainsim::camera {
namespace {

TEST(Lens, TheRimCheckAgreesWithTheWholeImageRemap) {
  // Validation checks a lens on the image's rim only (lensProblem); the camera inverts it at
  // every pixel (LensRemap). Over barrel and pincushion lenses up to folding, the two agree.
  const Intrinsics k = Intrinsics::fromHorizontalFov(160, 120, 80.0 * std::numbers::pi / 180.0);
  int folded = 0, fine = 0;
  for (double k1 = -1.6; k1 <= 0.61; k1 += 0.1)
    for (const double k2 : {0.0, 0.2}) {
      const Distortion d{k1, k2, 0.02, -0.01, 0.0};
      bool remap_ok = true;
      try {
        LensRemap remap(k, d);
      } catch (const std::exception&) {
        remap_ok = false;
      }
      EXPECT_EQ(lensProblem(k, d).empty(), remap_ok) << k1 << " " << k2;
      ++(remap_ok ? fine : folded);
    }
  EXPECT_GT(folded, 10) << fine;
  EXPECT_GT(fine, 10);
}

}  // namespace
}  // namespace trainsim::camera

namespace trainsim::camera {
namespace {

TEST(Exposure, OneStopDoublesTheLightNotTheEncodedValue) {
  // Gain 1 and no noise leave every value as it is; one stop more doubles each value's linear
  // light (to the 8-bit step) until it clips at white; a mid grey (sRGB 118, 18 % light) becomes
  // 36 % light (sRGB 162), not 236.
  const Exposure same(1.0, 0.0, 0.0), stop(2.0, 0.0, 0.0);
  EXPECT_TRUE(same.identity());
  for (int v = 0; v < 256; ++v) {
    const auto c = static_cast<std::uint8_t>(v);
    EXPECT_EQ(same(c, 0.0), c);
    const double want = std::min(1.0, 2.0 * srgbToLinear(v / 255.0));
    const double got = srgbToLinear(stop(c, 0.0) / 255.0);
    // Half an 8-bit step of the encoded value, in linear light, at the value's slope.
    const double step = std::max(srgbToLinear((stop(c, 0.0) + 0.5) / 255.0) - got,
                                 got - srgbToLinear((stop(c, 0.0) - 0.5) / 255.0));
    EXPECT_NEAR(got, want, step + 1e-12) << v;
  }
  EXPECT_EQ(stop(118, 0.0), 162);
  // Read noise of 2 linear steps: in the dark, where sRGB stretches, it shows as more steps.
  const Exposure noisy(1.0, 2.0, 0.0);
  EXPECT_GT(noisy(3, 1.0) - 3, 2);
  EXPECT_LE(noisy(250, 1.0) - 250, 1);
}

}  // namespace
}  // namespace trainsim::camera
