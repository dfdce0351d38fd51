// The movement system, the frame clock and the run stage, on synthetic trajectories.

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include <Eigen/Dense>

#include "../support/synthetic.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/frame_clock.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/movement.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {
namespace fs = std::filesystem;

class Recorder final : public SensorOf<TimeNs> {
 public:
  Recorder(const Trajectory& trajectory, std::string name, TimeNs period)
      : trajectory_(trajectory), name_(std::move(name)), period_(period) {}
  std::string name() const override { return name_; }
  std::string kind() const override { return "recorder"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return {}; }
  void begin(io::DatasetWriter&, const nlohmann::json&) override {}
  std::vector<std::int64_t> samples;
  std::vector<TimeNs> times;

 private:
  TimeNs read(std::int64_t k) const override { return trajectory_.sample(k).t_ns; }
  void write(std::int64_t k, TimeNs& t) override {
    samples.push_back(k);
    times.push_back(t);
  }
  const Trajectory& trajectory_;
  std::string name_;
  TimeNs period_;
};

fs::path freshDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("trainsim-sim-" + name);
  fs::remove_all(p);
  return p;
}

TEST(Movement, EachSensorFiresAtMultiplesOfItsPeriodOnTheSampleClock) {
  constexpr TimeNs ts = 10'000'000;
  const testing::StraightTrajectory traj(ts, 25, 10.0);
  std::vector<std::unique_ptr<Sensor>> sensors;
  sensors.push_back(std::make_unique<Recorder>(traj, "every", ts));
  sensors.push_back(std::make_unique<Recorder>(traj, "third", 3 * ts));
  const fs::path out = freshDir("fires");
  io::DatasetWriter writer(out, io::DatasetLayout(0), {"h", 1}, {});
  const auto readings = runMovement(traj, sensors, writer, {}).readings;
  const auto& every = static_cast<Recorder&>(*sensors[0]);
  const auto& third = static_cast<Recorder&>(*sensors[1]);
  EXPECT_EQ(every.samples.size(), 25u);
  EXPECT_EQ(third.samples, (std::vector<std::int64_t>{0, 3, 6, 9, 12, 15, 18, 21, 24}));
  for (std::size_t i = 0; i < third.samples.size(); ++i) {
    EXPECT_EQ(third.times[i], third.samples[i] * ts);  // time is bound to the sample
  }
  EXPECT_EQ(readings, (std::vector<std::int64_t>{25, 9}));
  fs::remove_all(out);
}

TEST(Movement, RejectsPeriodsThatAreNotMultiplesOfTs) {
  const testing::StraightTrajectory traj(10, 5, 1.0);
  std::vector<std::unique_ptr<Sensor>> sensors;
  sensors.push_back(std::make_unique<Recorder>(traj, "odd", 15));
  const fs::path out = freshDir("odd");
  io::DatasetWriter writer(out, io::DatasetLayout(0), {"h", 1}, {});
  EXPECT_THROW(runMovement(traj, sensors, writer, {}), RuntimeError);
  fs::remove_all(out);
}

TEST(Movement, ASensorFailureStopsTheRunAndReachesTheCaller) {
  // A render() that throws part-way: the run stops, the error reaches the caller, and the
  // chunks in flight are released (the ASan job checks for leaks).
  class Failing final : public SensorOf<int> {
   public:
    std::string name() const override { return "failing"; }
    std::string kind() const override { return "test"; }
    TimeNs period() const override { return 10; }
    std::vector<std::string> outputs() const override { return {}; }
    void begin(io::DatasetWriter&, const nlohmann::json&) override {}

   private:
    int read(std::int64_t k) const override {
      if (k == 57)
        throw RuntimeError("sensor failed at 57");
      return 0;
    }
    void write(std::int64_t k, int&) override { EXPECT_LT(k, 57); }
  };
  const testing::StraightTrajectory traj(10, 400, 1.0);
  std::vector<std::unique_ptr<Sensor>> sensors;
  sensors.push_back(std::make_unique<Failing>());
  const fs::path out = freshDir("failing");
  io::DatasetWriter writer(out, io::DatasetLayout(0), {"h", 1}, {});
  MovementOptions options;
  options.threads = 2;
  EXPECT_THROW(runMovement(traj, sensors, writer, options), RuntimeError);
  fs::remove_all(out);
}

TEST(Movement, ReadingsBeforeCountsFiringSamples) {
  EXPECT_EQ(readingsBefore(0, 10, 30), 0);
  EXPECT_EQ(readingsBefore(1, 10, 30), 1);
  EXPECT_EQ(readingsBefore(3, 10, 30), 1);
  EXPECT_EQ(readingsBefore(4, 10, 30), 2);
}

TEST(FrameClock, WritesExactTimesAndPosesRelativeToFrameZero) {
  constexpr TimeNs ts = 10'000'000;
  // Heading 0.7 rad: in the camera-0 frame of frame 0 the train still moves straight along +z.
  const testing::StraightTrajectory traj(ts, 101, 25.0, 0.7);
  std::vector<std::unique_ptr<Sensor>> sensors;
  Eigen::Isometry3d T_body_cam0 = Eigen::Isometry3d::Identity();  // no camera: at the body
  T_body_cam0.linear() = rotationBodyFromKittiCamera();
  sensors.push_back(std::make_unique<FrameClock>(10 * ts, traj, T_body_cam0));
  const fs::path out = freshDir("frameclock");
  {
    io::DatasetWriter writer(out, io::DatasetLayout(0), {"h", 1}, {});
    runMovement(traj, sensors, writer, {});
    writer.finish({});
  }
  std::istringstream times(io::readFile(out / "sequences/00/times.txt"));
  std::istringstream poses(io::readFile(out / "sequences/00/poses.txt"));
  std::string t;
  for (int i = 0; i <= 10; ++i) {
    ASSERT_TRUE(std::getline(times, t));
    EXPECT_EQ(t, i == 10 ? "1.000000000" : "0." + std::to_string(i) + "00000000");
    double m[12];
    for (double& v : m)
      ASSERT_TRUE(poses >> v);
    const double z = 25.0 * 0.1 * i;
    EXPECT_NEAR(m[0], 1.0, 1e-12);
    EXPECT_NEAR(m[5], 1.0, 1e-12);
    EXPECT_NEAR(m[10], 1.0, 1e-12);
    EXPECT_NEAR(m[3], 0.0, 1e-9);
    EXPECT_NEAR(m[7], 0.0, 1e-9);
    EXPECT_NEAR(m[11], z, 1e-9);
  }
  EXPECT_FALSE(std::getline(times, t));
  fs::remove_all(out);
}

std::string snapshot(const fs::path& root) {
  std::ostringstream s;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file())
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    s << f.lexically_relative(root).string() << "\n" << io::readFile(f) << "\n";
  }
  return s.str();
}

std::vector<std::unique_ptr<Sensor>> testSensors(const scenario::Scenario& sc,
                                                 const Trajectory& traj) {
  std::vector<std::unique_ptr<Sensor>> sensors;
  sensors.push_back(
      std::make_unique<testing::NoiseSensor>(traj, "fast", 10'000'000, sc.seed(), 64));
  sensors.push_back(
      std::make_unique<testing::NoiseSensor>(traj, "slow", 100'000'000, sc.seed(), 999));
  return sensors;
}

TEST(RunDataset, CancelledThenResumedRunIsByteIdenticalToAnUninterruptedOne) {
  // The schema's defaults: frames every 100 ms.
  const scenario::Scenario sc =
      scenario::Scenario::resolve(scenario::Json::object(), scenarioSchema());
  const testing::StraightTrajectory traj(10'000'000, 157, 30.0, 1.1);
  const fs::path a = freshDir("resume-a");
  const fs::path b = freshDir("resume-b");
  GenerateOptions opts;
  opts.out = a;
  const GenerateReport full = runDataset(sc, &traj, testSensors(sc, traj), opts);
  EXPECT_EQ(full.outputs.size(), 3u);
  EXPECT_EQ(full.outputs[0].readings, 16);  // frames 0..15 at 100 ms over 1.57 s

  // A sensor that requests cancellation part-way through the run.
  class Canceller final : public SensorOf<int> {
   public:
    explicit Canceller(std::atomic<bool>& flag) : flag_(flag) {}
    std::string name() const override { return "canceller"; }
    std::string kind() const override { return "test"; }
    TimeNs period() const override { return 10'000'000; }
    std::vector<std::string> outputs() const override { return {}; }
    void begin(io::DatasetWriter&, const nlohmann::json&) override {}

   private:
    int read(std::int64_t) const override { return 0; }
    void write(std::int64_t k, int&) override {
      if (k == 73)
        flag_ = true;
    }
    std::atomic<bool>& flag_;
  };
  std::atomic<bool> cancel{false};
  opts.out = b;
  opts.cancel = &cancel;
  auto sensors = testSensors(sc, traj);
  sensors.push_back(std::make_unique<Canceller>(cancel));
  EXPECT_THROW(runDataset(sc, &traj, std::move(sensors), opts), Cancelled);
  EXPECT_FALSE(fs::exists(b / "manifest.json"));
  cancel = false;
  opts.policy.resume = true;
  runDataset(sc, &traj, testSensors(sc, traj), opts);
  EXPECT_EQ(snapshot(a), snapshot(b));
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(Schema, DefaultScenarioIsValidAndComplete) {
  const scenario::Scenario sc = loadScenario("");
  EXPECT_EQ(sc.seed(), 5u);  // configs/default.json: a route with a station, a bridge and tunnels
  // `trainsim defaults` output validates to itself.
  const scenario::Scenario again =
      scenario::Scenario::resolve(sc.json(), scenarioSchema(), "defaults");
  EXPECT_EQ(again.text(), sc.text());
  EXPECT_EQ(loadScenario("", 7).seed(), 7u);
}

}  // namespace
}  // namespace trainsim::sim
