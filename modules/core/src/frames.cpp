#include "trainsim/core/frames.hpp"

#include <fmt/format.h>

#include <iterator>

namespace trainsim {

Eigen::Matrix3d attitude(double yaw_rad, double pitch_rad, double roll_rad) {
  return (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(-pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d Mount::T_body_sensor() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = r_body_sensor;
  T.translation() = position_m;
  return T;
}

Eigen::Matrix3d rotationBodyFromKittiCamera() {
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return r;
}

Eigen::Matrix3d rotationBodyFromKittiVelodyne() {
  return Eigen::Matrix3d::Identity();
}

Eigen::Isometry3d kittiTr(const Eigen::Isometry3d& T_body_cam,
                          const Eigen::Isometry3d& T_body_velo) {
  return T_body_cam.inverse() * T_body_velo;
}

std::string kittiCalibLine(std::string_view key, const Eigen::Matrix<double, 3, 4>& m) {
  std::string line = fmt::format("{}:", key);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      fmt::format_to(std::back_inserter(line), " {:.12e}", m(r, c));
  return line;
}

}  // namespace trainsim
