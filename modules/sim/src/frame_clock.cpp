#include "trainsim/sim/frame_clock.hpp"

#include <fmt/format.h>

namespace trainsim::sim {
FrameClock::FrameClock(TimeNs period, const Trajectory& trajectory,
                       const Eigen::Isometry3d& T_body_cam0)
    : trajectory_(trajectory),
      period_(period),
      T_body_cam0_(T_body_cam0),
      T_cam0_world_first_(trajectory.sampleCount() > 0
                              ? (trajectory.sample(0).pose() * T_body_cam0).inverse()
                              : Eigen::Isometry3d::Identity()) {}

void FrameClock::begin(io::DatasetWriter& writer, const nlohmann::json& /*state*/) {
  const std::vector<std::string> files = outputs();
  times_ = &writer.appendFile(writer.layout().inSequence(files[0]));
  poses_ = &writer.appendFile(writer.layout().inSequence(files[1]));
}

FrameLines FrameClock::read(std::int64_t k) const {
  const TrajectorySample sample = trajectory_.sample(k);
  // Relative to frame 0, so positions stay small and 12 significant digits keep sub-micrometre
  // resolution even for long routes far from the scenario origin.
  // The first frame's is the identity by definition (KITTI's first line), not the rounding of
  // a pose times its inverse.
  const Eigen::Isometry3d T =
      k == 0 ? Eigen::Isometry3d::Identity() : T_cam0_world_first_ * (sample.pose() * T_body_cam0_);
  const Eigen::Matrix<double, 3, 4> m = T.matrix().topRows<3>();
  return {fmt::format("{}.{:09}\n", sample.t_ns / kNsPerSecond, sample.t_ns % kNsPerSecond),
          fmt::format("{:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} {:.12e} "
                      "{:.12e} {:.12e} {:.12e}\n",
                      m(0, 0), m(0, 1), m(0, 2), m(0, 3), m(1, 0), m(1, 1), m(1, 2), m(1, 3),
                      m(2, 0), m(2, 1), m(2, 2), m(2, 3))};
}

void FrameClock::write(std::int64_t /*k*/, FrameLines& lines) {
  times_->write(lines.time);
  poses_->write(lines.pose);
}

}  // namespace trainsim::sim
