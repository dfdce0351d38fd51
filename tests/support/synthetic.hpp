#pragma once

// Test doubles for the movement system and the dataset writer: a trajectory with a closed
// form and a sensor whose output exercises every resume path (per-frame files, an append-only
// CSV, random draws keyed by sample index, and state carried across checkpoints).

#include <atomic>
#include <memory>
#include <string>

#include "trainsim/core/random.hpp"
#include "trainsim/sim/sensor.hpp"
#include "trainsim/sim/trajectory.hpp"

namespace trainsim::testing {

/// Straight, level run along `heading_rad` (from east, counter-clockwise) at constant speed.
class StraightTrajectory final : public sim::Trajectory {
 public:
  StraightTrajectory(TimeNs sample_period, std::int64_t samples, double speed_m_s,
                     double heading_rad = 0.0)
      : ts_(sample_period), n_(samples), v_(speed_m_s), heading_(heading_rad) {}
  TimeNs samplePeriod() const override { return ts_; }
  std::int64_t sampleCount() const override { return n_; }
  sim::TrajectorySample at(TimeNs t) const override;

 private:
  TimeNs ts_;
  std::int64_t n_;
  double v_;
  double heading_;
};

/// Writes, at each reading, `<name>/NNNNNN.bin` (payload_bytes of counter-based noise keyed by
/// the sample index) and one line of `<name>.csv` with a random walk whose value is carried in
/// state(). `delay_ms` slows it down so that a test can kill the process part-way.
/// The payload is rendered (in parallel), the walk and the files are committed in order.
struct NoiseReading {
  TimeNs t_ns = 0;
  double speed_m_s = 0.0;
  std::string payload;
  double step = 0.0;
};

class NoiseSensor final : public sim::SensorOf<NoiseReading> {
 public:
  NoiseSensor(const sim::Trajectory& trajectory, std::string name, TimeNs period,
              std::uint64_t seed, std::size_t payload_bytes, int delay_ms = 0);
  std::string name() const override { return name_; }
  std::string kind() const override { return "test_noise"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return {name_ + ".csv", name_ + "/"}; }
  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override;
  nlohmann::json state() const override;

 private:
  NoiseReading read(std::int64_t k) const override;
  void write(std::int64_t k, NoiseReading& reading) override;

  const sim::Trajectory& trajectory_;
  std::string name_;
  TimeNs period_;
  RandomStream stream_;
  std::size_t payload_bytes_;
  int delay_ms_;
  io::DatasetWriter* writer_ = nullptr;
  io::AppendFile* csv_ = nullptr;
  double walk_ = 0.0;
  std::int64_t readings_ = 0;
};

/// A synthetic heavy frame sensor: each render() does `work` rounds of counter-based
/// arithmetic (deterministic, about 0.1 µs a round) and records how many renders ran at once;
/// commit() writes one line of <name>.csv with a digest of the result. Stands in for a LiDAR or
/// camera in the run loop's thread test and benchmark.
class BusySensor final : public sim::SensorOf<std::uint64_t> {
 public:
  /// Counts render() calls running at once; shared so it outlives the run that owns the sensor.
  struct Gauge {
    std::atomic<int> running{0};
    std::atomic<int> peak{0};  ///< the largest number of render() calls running at once
    /// If set, a render() waits (up to 5 s) until this many run at once, so that a loaded
    /// machine's scheduler cannot make a pool of N threads look smaller than N.
    int rendezvous = 0;
  };

  BusySensor(std::string name, TimeNs period, std::uint64_t seed, std::int64_t work,
             std::shared_ptr<Gauge> gauge = std::make_shared<Gauge>());
  std::string name() const override { return name_; }
  std::string kind() const override { return "test_busy"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return {name_ + ".csv"}; }
  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override;

 private:
  std::uint64_t read(std::int64_t k) const override;
  void write(std::int64_t k, std::uint64_t& digest) override;

  std::string name_;
  TimeNs period_;
  RandomStream stream_;
  std::int64_t work_;
  std::shared_ptr<Gauge> gauge_;
  io::AppendFile* csv_ = nullptr;
};

}  // namespace trainsim::testing
