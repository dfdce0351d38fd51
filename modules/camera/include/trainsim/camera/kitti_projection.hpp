#pragma once
// A camera's view of a LiDAR's points as a KITTI calib.txt states it, for readers of datasets
// (the studio draws scans on pictures with it).
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/camera/lens.hpp"

namespace trainsim::camera {

/// Tr (or Tr_N) takes a LiDAR's points into camera 0's frame, the camera's P = K [R | t] from
/// there into its image, and its lens (calib.txt's D line, OpenCV's k1 k2 p1 p2 k3) bends the
/// rays between [R | t] and K. P is split into K and [R | t] for that: K K^T = M M^T for
/// M = K R, and K is upper triangular, so K is a Cholesky factor (taken of the matrix reversed
/// in both axes, so that it comes out upper).
struct KittiProjection {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Eigen::Isometry3d camera_from_lidar = Eigen::Isometry3d::Identity();
  std::optional<Distortion> lens;

  /// From calib.txt's P and Tr (3 × 4, row by row as the file has them) and the camera's
  /// distortion if it has one. nullopt, with the reason in `problem`, when P's left 3 × 3 is
  /// not an upper-triangular K with a positive diagonal times a rotation.
  static std::optional<KittiProjection> fromCalib(const Eigen::Matrix<double, 3, 4>& P,
                                                  const Eigen::Matrix<double, 3, 4>& Tr,
                                                  std::optional<Distortion> lens,
                                                  std::string& problem);

  /// The pixel (u, v, integer at pixel centres) a point in the LiDAR's frame lands on in a
  /// width × height image, and its depth along the camera's optical axis; nullopt behind the
  /// camera, outside the image, or (with a lens) more than half an image beyond its rim, where
  /// the distortion polynomial folds back.
  std::optional<Eigen::Vector3d> project(const Eigen::Vector3d& p_lidar, int width,
                                         int height) const;
};

}  // namespace trainsim::camera
