// KittiProjection: calib.txt's P = K [R | t] split back into K and [R | t] (recovered exactly for
// a turned, shifted camera), points projected as the camera model and the lens model project
// them, and what cannot be a camera's P refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>

#include "trainsim/camera/camera_model.hpp"
#include "trainsim/camera/kitti_projection.hpp"

namespace trainsim::camera {
namespace {

struct Rig {
  Intrinsics k{1242, 375, 721.5, 716.0, 609.6, 172.9};
  Eigen::Isometry3d camera_from_cam0 = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d cam0_from_lidar = Eigen::Isometry3d::Identity();
  Rig() {
    camera_from_cam0.linear() = (Eigen::AngleAxisd(0.09, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
    camera_from_cam0.translation() = Eigen::Vector3d(-0.54, 0.06, -0.2);
    // KITTI's velodyne axes (x ahead, y left, z up) into camera axes (x right, y down, z ahead),
    // slightly tilted, with a lever arm.
    Eigen::Matrix3d axes;
    axes << 0, -1, 0, 0, 0, -1, 1, 0, 0;
    cam0_from_lidar.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()) * axes;
    cam0_from_lidar.translation() = Eigen::Vector3d(0.01, -0.08, -0.27);
  }
  Eigen::Matrix<double, 3, 4> P() const {
    return k.matrix() * camera_from_cam0.matrix().topRows<3>();
  }
  Eigen::Matrix<double, 3, 4> Tr() const { return cam0_from_lidar.matrix().topRows<3>(); }
};

TEST(KittiProjection, SplitsPBackIntoKAndTheCamerasPose) {
  const Rig rig;
  std::string problem;
  const auto projection = KittiProjection::fromCalib(rig.P(), rig.Tr(), std::nullopt, problem);
  ASSERT_TRUE(projection) << problem;
  EXPECT_TRUE(projection->K.isApprox(rig.k.matrix(), 1e-12)) << projection->K;
  EXPECT_TRUE(projection->camera_from_lidar.matrix().isApprox(
      (rig.camera_from_cam0 * rig.cam0_from_lidar).matrix(), 1e-12));
  // Points ahead of the sensor project where the pinhole model puts them, with their depth.
  int inside = 0;
  for (int i = -20; i <= 20; ++i)
    for (int j = -5; j <= 5; ++j) {
      const Eigen::Vector3d p(8.0 + 3.0 * (i + 20), 0.7 * i, 0.3 * j);
      const Eigen::Vector3d c = rig.camera_from_cam0 * rig.cam0_from_lidar * p;
      const Eigen::Vector2d want = rig.k.project(c);
      const auto got = projection->project(p, rig.k.width, rig.k.height);
      const bool in_image = want.x() > -0.5 && want.x() < rig.k.width - 0.5 && want.y() > -0.5 &&
                            want.y() < rig.k.height - 0.5;
      ASSERT_EQ(got.has_value(), in_image) << p.transpose();
      if (!got)
        continue;
      ++inside;
      EXPECT_NEAR(got->x(), want.x(), 1e-9);
      EXPECT_NEAR(got->y(), want.y(), 1e-9);
      EXPECT_NEAR(got->z(), c.z(), 1e-12);
    }
  EXPECT_GT(inside, 100);
  // Behind the camera: nothing.
  EXPECT_FALSE(projection->project(Eigen::Vector3d(-10.0, 0.0, 0.0), 1242, 375));
}

TEST(KittiProjection, ALensBendsTheRaysBetweenThePoseAndK) {
  const Rig rig;
  const Distortion lens{-0.28, 0.07, 0.0004, -0.0002, 0.0};
  std::string problem;
  const auto projection = KittiProjection::fromCalib(rig.P(), rig.Tr(), lens, problem);
  ASSERT_TRUE(projection) << problem;
  int bent = 0;
  for (int i = -10; i <= 10; ++i) {
    const Eigen::Vector3d p(20.0, 1.1 * i, -1.5);
    const Eigen::Vector3d c = rig.camera_from_cam0 * rig.cam0_from_lidar * p;
    const Eigen::Vector2d xy = lens.apply(Eigen::Vector2d(c.x() / c.z(), c.y() / c.z()));
    const Eigen::Vector2d want(rig.k.fx * xy.x() + rig.k.cx, rig.k.fy * xy.y() + rig.k.cy);
    const auto got = projection->project(p, rig.k.width, rig.k.height);
    if (!got)
      continue;
    EXPECT_NEAR(got->x(), want.x(), 1e-9);
    EXPECT_NEAR(got->y(), want.y(), 1e-9);
    bent += (want - rig.k.project(c)).norm() > 1.0;
  }
  EXPECT_GT(bent, 5);  // the lens moved them by more than a pixel
}

TEST(KittiProjection, RefusesWhatCannotBeACamerasP) {
  const Rig rig;
  std::string problem;
  Eigen::Matrix<double, 3, 4> mirrored = rig.P();
  mirrored.row(1) *= -1.0;  // K R with a reflection for R: no camera images like that
  EXPECT_FALSE(KittiProjection::fromCalib(mirrored, rig.Tr(), std::nullopt, problem));
  EXPECT_NE(problem.find("not K [R | t]"), std::string::npos);
  EXPECT_FALSE(KittiProjection::fromCalib(Eigen::Matrix<double, 3, 4>::Zero(), rig.Tr(),
                                          std::nullopt, problem));
  Eigen::Matrix<double, 3, 4> nan = rig.P();
  nan(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(KittiProjection::fromCalib(nan, rig.Tr(), std::nullopt, problem));
}

}  // namespace
}  // namespace trainsim::camera
