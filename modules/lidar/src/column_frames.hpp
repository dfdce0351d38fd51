#pragma once
// Private to the LiDAR module: how the scanner lays out each column's ray frame and deskewing
// (Scanner::Scratch::frames), shared by the rays' set-up (scanner_rays.cpp) and the returns
// (lidar.cpp; packet_returns.cpp is handed the layout in its PacketSetup).
#include <cstddef>

#include <Eigen/Core>

namespace trainsim::lidar::detail {

// Columns between the poses asked of the caller (the ones between are interpolated).
constexpr int kPoseStep = 16;

// A column's ray frame and deskewing, by lane (Scratch::frames: field f of column c at
// f × padded + c, so eight neighbouring columns' values are one load): the sensor's rotation to
// world axes (row-major), the ray origin relative to the scene's origin, the deskewing's
// rotation (row-major) and its translation, all in float (the sensor's reach is small).
constexpr std::size_t kRot = 0, kOrigin = 9, kDeskew = 12, kShift = 21, kFrameFields = 24;

// Point `v` of column c's sensor frame deskewed to the frame time.
inline Eigen::Vector3f deskewed(const float* frames, std::size_t padded, std::size_t c,
                                const Eigen::Vector3f& v) {
  const auto f = [&](std::size_t field) { return frames[field * padded + c]; };
  return {f(kDeskew) * v.x() + f(kDeskew + 1) * v.y() + f(kDeskew + 2) * v.z() + f(kShift),
          f(kDeskew + 3) * v.x() + f(kDeskew + 4) * v.y() + f(kDeskew + 5) * v.z() + f(kShift + 1),
          f(kDeskew + 6) * v.x() + f(kDeskew + 7) * v.y() + f(kDeskew + 8) * v.z() + f(kShift + 2)};
}

}  // namespace trainsim::lidar::detail
