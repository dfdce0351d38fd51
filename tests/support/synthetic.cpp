#include "synthetic.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

namespace trainsim::testing {

sim::TrajectorySample StraightTrajectory::sample(std::int64_t k) const {
  sim::TrajectorySample s;
  s.t_ns = k * ts_;
  const double t = toSeconds(s.t_ns);
  const Eigen::Vector3d dir(std::cos(heading_), std::sin(heading_), 0.0);
  s.chainage_m = v_ * t;
  s.p_world = dir * s.chainage_m;
  s.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(heading_, Eigen::Vector3d::UnitZ()));
  s.v_world = dir * v_;
  return s;
}

NoiseSensor::NoiseSensor(std::string name, TimeNs period, std::uint64_t seed,
                         std::size_t payload_bytes, int delay_ms)
    : name_(std::move(name)),
      period_(period),
      stream_(seed, "test." + name_),
      payload_bytes_(payload_bytes),
      delay_ms_(delay_ms) {}

void NoiseSensor::begin(io::DatasetWriter& writer, const nlohmann::json& state) {
  writer_ = &writer;
  const auto dir = writer.sequenceDir().lexically_relative(writer.root());
  csv_ = &writer.appendFile(dir / (name_ + ".csv"));
  if (!state.is_null()) {
    walk_ = state.at("walk").get<double>();
    readings_ = state.at("readings").get<std::int64_t>();
  } else {
    csv_->write("t_ns,walk,speed_m_s\n");
  }
}

void NoiseSensor::capture(std::int64_t k, const sim::TrajectorySample& sample) {
  if (delay_ms_ > 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms_));
  std::string payload(payload_bytes_, '\0');
  for (std::size_t i = 0; i < payload_bytes_; i += 32) {
    const auto bits = stream_.bits(static_cast<std::uint64_t>(k), i / 32);
    std::memcpy(payload.data() + i, bits.data(), std::min<std::size_t>(32, payload_bytes_ - i));
  }
  const auto dir = writer_->sequenceDir().lexically_relative(writer_->root());
  writer_->writeFile(dir / name_ / fmt::format("{:06}.bin", readings_), payload);
  walk_ += stream_.normal4(static_cast<std::uint64_t>(k), 1u << 20)[0];
  csv_->write(fmt::format("{},{:.17g},{:.17g}\n", sample.t_ns, walk_, sample.v_world.norm()));
  ++readings_;
}

nlohmann::json NoiseSensor::state() const {
  return {{"walk", walk_}, {"readings", readings_}};
}

}  // namespace trainsim::testing
