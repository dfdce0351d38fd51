// One test per frame convention (core/frames.hpp), named after it.
#include <gtest/gtest.h>

#include "trainsim/core/frames.hpp"

namespace trainsim {
namespace {

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(),
                      kZ = Eigen::Vector3d::UnitZ();

void expectNear(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  EXPECT_LT((a - b).norm(), 1e-12) << a.transpose() << " vs " << b.transpose();
}

TEST(Convention, AttitudeYawTurnsForwardTowardsLeft) {
  expectNear(attitude(kRadPerDeg * 90, 0, 0) * kX, kY);
}

TEST(Convention, AttitudePitchIsPositiveNoseUp) {
  // Body and mounts alike: a positive pitch raises the x axis.
  const Eigen::Vector3d nose = attitude(0, kRadPerDeg * 10, 0) * kX;
  EXPECT_GT(nose.z(), 0.17);
  expectNear(attitude(0, kRadPerDeg * 90, 0) * kX, kZ);
}

TEST(Convention, AttitudeRollIsPositiveRightSideDown) {
  // y (left) rises: the right side goes down.
  expectNear(attitude(0, 0, kRadPerDeg * 90) * kY, kZ);
}

TEST(Convention, AttitudeAppliesYawThenPitchThenRollIntrinsically) {
  const double yaw = 0.3, pitch = 0.2, roll = -0.1;
  const Eigen::Matrix3d expected =
      (Eigen::AngleAxisd(yaw, kZ) * Eigen::AngleAxisd(-pitch, kY) * Eigen::AngleAxisd(roll, kX))
          .toRotationMatrix();
  EXPECT_LT((attitude(yaw, pitch, roll) - expected).norm(), 1e-15);
}

TEST(Convention, MountPitchSignMatchesTheBody) {
  // A sensor mounted with pitch_deg = +5 looks 5° above the body's x axis.
  Mount m;
  m.r_body_sensor = attitude(0, kRadPerDeg * 5, 0);
  const Eigen::Vector3d boresight = m.T_body_sensor().linear() * kX;
  EXPECT_NEAR(std::atan2(boresight.z(), boresight.x()), kRadPerDeg * 5, 1e-15);
}

TEST(Convention, MountMapsSensorPointsIntoTheBody) {
  Mount m;
  m.position_m = {2.0, -0.5, 3.0};
  m.r_body_sensor = attitude(kRadPerDeg * 90, 0, 0);
  // A point 1 m along the sensor's x lies 1 m to the body's left of the mount.
  expectNear(m.T_body_sensor() * kX, Eigen::Vector3d(2.0, 0.5, 3.0));
}

TEST(Convention, KittiCameraAxesAreRightDownForward) {
  const Eigen::Matrix3d r = rotationBodyFromKittiCamera();
  EXPECT_DOUBLE_EQ(r.determinant(), 1.0);
  EXPECT_EQ(r * kZ, kX);   // forward
  EXPECT_EQ(r * kX, -kY);  // right
  EXPECT_EQ(r * kY, -kZ);  // down
}

TEST(Convention, KittiVelodyneAxesAreForwardLeftUp) {
  const Eigen::Matrix3d r = rotationBodyFromKittiVelodyne();
  EXPECT_EQ(r * kX, kX);
  EXPECT_EQ(r * kY, kY);
  EXPECT_EQ(r * kZ, kZ);
}

TEST(Convention, KittiTrMapsVelodynePointsIntoTheCamera) {
  // Camera 1.5 m above the body origin, LiDAR 2 m above and 1 m ahead, both at body attitude.
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.linear() = rotationBodyFromKittiCamera();
  T_body_cam.translation() = Eigen::Vector3d(0, 0, 1.5);
  Eigen::Isometry3d T_body_velo = Eigen::Isometry3d::Identity();
  T_body_velo.translation() = Eigen::Vector3d(1, 0, 2);
  const Eigen::Isometry3d Tr = kittiTr(T_body_cam, T_body_velo);
  // The LiDAR's origin is 1 m ahead (camera z) and 0.5 m above (camera −y) of the camera.
  expectNear(Tr * Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -0.5, 1));
  // A point 10 m ahead of the LiDAR is 11 m ahead of the camera.
  expectNear(Tr * Eigen::Vector3d(10, 0, 0), Eigen::Vector3d(0, -0.5, 11));
}

TEST(Convention, StandardGravityIsTheCgpmValue) {
  EXPECT_EQ(kStandardGravity_m_s2, 9.80665);
}

}  // namespace
}  // namespace trainsim
