#include "trainsim/camera/kitti_projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace trainsim::camera {

std::optional<KittiProjection> KittiProjection::fromCalib(const Eigen::Matrix<double, 3, 4>& P,
                                                          const Eigen::Matrix<double, 3, 4>& Tr,
                                                          std::optional<Distortion> lens,
                                                          std::string& problem) {
  KittiProjection out;
  out.lens = lens;
  const Eigen::Matrix3d M = P.leftCols<3>();
  const Eigen::Matrix3d J = Eigen::Matrix3d::Identity().rowwise().reverse();
  const Eigen::LLT<Eigen::Matrix3d> llt(J * M * M.transpose() * J);
  bool ok = M.allFinite() && Tr.allFinite() && llt.info() == Eigen::Success;
  if (ok) {
    out.K = J * Eigen::Matrix3d(llt.matrixL()) * J;
    out.K /= out.K(2, 2);
  }
  const Eigen::Matrix3d R = out.K.inverse() * M;
  ok = ok && R.allFinite() && (R * R.transpose()).isIdentity(1e-6) && R.determinant() > 0.0;
  if (!ok) {
    problem = "P is not K [R | t] (K upper triangular, R a rotation)";
    return std::nullopt;
  }
  Eigen::Isometry3d camera_from_cam0 = Eigen::Isometry3d::Identity();
  camera_from_cam0.linear() = R;
  camera_from_cam0.translation() = out.K.inverse() * P.col(3);
  Eigen::Isometry3d cam0_from_lidar = Eigen::Isometry3d::Identity();
  cam0_from_lidar.matrix().topRows<3>() = Tr;
  out.camera_from_lidar = camera_from_cam0 * cam0_from_lidar;
  return out;
}

std::optional<Eigen::Vector3d> KittiProjection::project(const Eigen::Vector3d& p_lidar, int width,
                                                        int height) const {
  const Eigen::Vector3d c = camera_from_lidar * p_lidar;
  if (!(c.z() > 1e-3))
    return std::nullopt;
  Eigen::Vector2d xy(c.x() / c.z(), c.y() / c.z());
  if (lens) {
    const Eigen::Vector3d pinhole = K * Eigen::Vector3d(xy.x(), xy.y(), 1.0);
    if (pinhole.x() < -0.5 * width || pinhole.x() > 1.5 * width || pinhole.y() < -0.5 * height ||
        pinhole.y() > 1.5 * height)
      return std::nullopt;
    xy = lens->apply(xy);
  }
  const Eigen::Vector3d px = K * Eigen::Vector3d(xy.x(), xy.y(), 1.0);
  if (!(px.x() > -0.5 && px.x() < width - 0.5 && px.y() > -0.5 && px.y() < height - 0.5))
    return std::nullopt;
  return Eigen::Vector3d(px.x(), px.y(), c.z());
}

}  // namespace trainsim::camera
