#include "synthetic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

namespace trainsim::testing {

sim::TrajectorySample StraightTrajectory::at(TimeNs t_ns) const {
  sim::TrajectorySample s;
  s.t_ns = std::clamp<TimeNs>(t_ns, 0, endTime());
  const double t = toSeconds(s.t_ns);
  const Eigen::Vector3d dir(std::cos(heading_), std::sin(heading_), 0.0);
  s.chainage_m = v_ * t;
  s.p_world = dir * s.chainage_m;
  s.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(heading_, Eigen::Vector3d::UnitZ()));
  s.v_world = dir * v_;
  return s;
}

NoiseSensor::NoiseSensor(const sim::Trajectory& trajectory, std::string name, TimeNs period,
                         std::uint64_t seed, std::size_t payload_bytes, int delay_ms)
    : trajectory_(trajectory),
      name_(std::move(name)),
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

NoiseReading NoiseSensor::read(std::int64_t k) const {
  if (delay_ms_ > 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms_));
  NoiseReading r;
  const sim::TrajectorySample sample = trajectory_.sample(k);
  r.t_ns = sample.t_ns;
  r.speed_m_s = sample.v_world.norm();
  r.payload.assign(payload_bytes_, '\0');
  for (std::size_t i = 0; i < payload_bytes_; i += 32) {
    const auto bits = stream_.bits(static_cast<std::uint64_t>(k), i / 32);
    std::memcpy(r.payload.data() + i, bits.data(), std::min<std::size_t>(32, payload_bytes_ - i));
  }
  r.step = stream_.normal4(static_cast<std::uint64_t>(k), 1u << 20)[0];
  return r;
}

void NoiseSensor::write(std::int64_t, NoiseReading& r) {
  const auto dir = writer_->sequenceDir().lexically_relative(writer_->root());
  writer_->writeFile(dir / name_ / fmt::format("{:06}.bin", readings_), r.payload);
  walk_ += r.step;
  csv_->write(fmt::format("{},{:.17g},{:.17g}\n", r.t_ns, walk_, r.speed_m_s));
  ++readings_;
}

nlohmann::json NoiseSensor::state() const {
  return {{"walk", walk_}, {"readings", readings_}};
}

BusySensor::BusySensor(std::string name, TimeNs period, std::uint64_t seed, std::int64_t work,
                       std::shared_ptr<Gauge> gauge)
    : name_(std::move(name)),
      period_(period),
      stream_(seed, "test." + name_),
      work_(work),
      gauge_(std::move(gauge)) {}

void BusySensor::begin(io::DatasetWriter& writer, const nlohmann::json& state) {
  const auto dir = writer.sequenceDir().lexically_relative(writer.root());
  csv_ = &writer.appendFile(dir / (name_ + ".csv"));
  if (state.is_null())
    csv_->write("k,digest\n");
}

std::uint64_t BusySensor::read(std::int64_t k) const {
  const int now = gauge_->running.fetch_add(1) + 1;
  int peak = gauge_->peak.load();
  while (now > peak && !gauge_->peak.compare_exchange_weak(peak, now)) {
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (gauge_->peak.load() < gauge_->rendezvous && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    const int running = gauge_->running.load();
    peak = gauge_->peak.load();
    while (running > peak && !gauge_->peak.compare_exchange_weak(peak, running)) {
    }
  }
  std::uint64_t digest = 0;
  for (std::int64_t i = 0; i < work_; ++i)
    digest ^= stream_.bits(static_cast<std::uint64_t>(k), static_cast<std::uint64_t>(i))[0];
  gauge_->running.fetch_sub(1);
  return digest;
}

void BusySensor::write(std::int64_t k, std::uint64_t& digest) {
  csv_->write(fmt::format("{},{:016x}\n", k, digest));
}

}  // namespace trainsim::testing
