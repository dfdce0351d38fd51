// The run loop's parallel speed-up on a synthetic heavy frame sensor: a 10 Hz sensor whose
// render() costs about 20 ms (counter-based arithmetic, like a LiDAR frame's ray casting), next
// to a 100 Hz light sensor and the frame clock, through the real run stage (sim::runDataset:
// dataset folder, checkpoints, manifest). Baseline: the same run on one worker thread,
// measured in the same process. Also checks that every thread count wrote the same bytes.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "../tests/support/synthetic.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/schema.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Result {
  double seconds;
  int render_threads;
  std::string busy_csv;
};

Result run(const trainsim::scenario::Scenario& sc, const trainsim::sim::Trajectory& traj,
           int threads, std::int64_t work) {
  using namespace trainsim;
  const TimeNs frame = sc.get<TimeNs>("dataset.frame_period_ns");
  std::vector<std::unique_ptr<sim::Sensor>> sensors;
  sensors.push_back(std::make_unique<testing::BusySensor>("heavy", frame, sc.seed(), work));
  sensors.push_back(
      std::make_unique<testing::NoiseSensor>(traj, "light", frame / 10, sc.seed(), 64));
  sim::GenerateOptions options;
  options.out = fs::temp_directory_path() / fmt::format("trainsim-bench-run-loop-{}", threads);
  options.policy.force = true;
  options.threads = threads;
  const auto t0 = Clock::now();
  const sim::GenerateReport report = sim::runDataset(sc, &traj, std::move(sensors), options);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  Result r{seconds, report.render_threads,
           io::readFile(options.out / io::DatasetLayout(0).inSequence("heavy.csv"))};
  fs::remove_all(options.out);
  return r;
}

}  // namespace

int main() {
  using namespace trainsim;
  const scenario::Scenario sc = sim::loadScenario("");
  const testing::StraightTrajectory traj(sc.get<TimeNs>("trajectory.sample_period_ns"), 1001, 30.0);
  constexpr std::int64_t kWork = 1'500'000;  // counter-based draws per frame
  run(sc, traj, 1, kWork / 50);              // warm-up
  const Result one = run(sc, traj, 1, kWork);
  fmt::print("run loop, 100 heavy frames + 1000 light readings over 10 s of trajectory\n");
  fmt::print("{:>8} {:>10} {:>10} {:>16} {:>10}\n", "threads", "time [s]", "speed-up",
             "render threads", "bytes");
  fmt::print("{:>8} {:>10.3f} {:>10.2f} {:>16} {:>10}\n", 1, one.seconds, 1.0, one.render_threads,
             "baseline");
  for (int threads : {2, 4}) {
    const Result r = run(sc, traj, threads, kWork);
    fmt::print("{:>8} {:>10.3f} {:>10.2f} {:>16} {:>10}\n", threads, r.seconds,
               one.seconds / r.seconds, r.render_threads,
               r.busy_csv == one.busy_csv ? "identical" : "DIFFER");
  }
  return 0;
}
