#pragma once

#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// One frame's lines of times.txt and poses.txt.
struct FrameLines {
  std::string time;
  std::string pose;
};

/// The dataset's frame clock: at every frame (dataset.frame_period_ns) it writes one line to
/// sequences/NN/times.txt (seconds since the start, fixed point, exact to the nanosecond) and
/// one to poses.txt (KITTI odometry convention: the 3x4 row-major pose of the camera-0 frame
/// at this frame, expressed in the camera-0 frame of frame 0).
///
/// Camera axes follow KITTI: x right, y down, z forward. Camera 0 is the first camera's mount,
/// or without a camera the body reference point with those axes (referenceCameraPose).

class FrameClock final : public SensorOf<FrameLines> {
 public:
  FrameClock(TimeNs period, const Trajectory& trajectory, const Eigen::Isometry3d& T_body_cam0);

  static constexpr const char* kKind = "frames";

  std::string name() const override { return kKind; }
  std::string kind() const override { return kKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override {
    return {io::DatasetLayout::kTimes, io::DatasetLayout::kPoses};
  }
  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override;

 private:
  FrameLines read(std::int64_t k) const override;
  void write(std::int64_t k, FrameLines& lines) override;

  const Trajectory& trajectory_;
  TimeNs period_;
  Eigen::Isometry3d T_body_cam0_;
  Eigen::Isometry3d T_cam0_world_first_;  // inverse pose of camera 0 at frame 0
  io::AppendFile* times_ = nullptr;
  io::AppendFile* poses_ = nullptr;
};

}  // namespace trainsim::sim
