// The frame-sensor run loop: --threads N really renders on N threads, the dataset bytes do not
// depend on it, and sensors of one kind keep apart (names, files, random streams).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../support/synthetic.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {
namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("trainsim-runloop-" + name);
  fs::remove_all(p);
  return p;
}

// Every file of a folder with its bytes, in path order.
std::string snapshot(const fs::path& root) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file())
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::ostringstream s;
  for (const auto& f : files)
    s << f.lexically_relative(root).string() << "\n" << io::readFile(f) << "\n";
  return s.str();
}

TEST(RunLoop, RendersOnExactlyTheRequestedNumberOfThreadsWithIdenticalBytes) {
  // Frames of 100 ms: 24 of them, enough for every worker.
  const scenario::Scenario sc = scenario::Scenario::resolve(
      {{"dataset", {{"frame_period_ns", 100'000'000}}}}, scenarioSchema());
  const TimeNs frame = sc.get<TimeNs>("dataset.frame_period_ns");
  const testing::StraightTrajectory traj(sc.get<TimeNs>("trajectory.sample_period_ns"), 241, 20.0);
  std::string reference;
  for (int threads : {1, 2, 4}) {
    auto gauge = std::make_shared<testing::BusySensor::Gauge>();
    gauge->rendezvous = threads;
    std::vector<std::unique_ptr<Sensor>> sensors;
    // Several milliseconds of work a frame, so every worker gets frames to render.
    sensors.push_back(
        std::make_unique<testing::BusySensor>("busy", frame, sc.seed(), 400'000, gauge));
    sensors.push_back(
        std::make_unique<testing::NoiseSensor>(traj, "noise", frame / 10, sc.seed(), 16));
    GenerateOptions options;
    options.out = freshDir("threads" + std::to_string(threads));
    options.threads = threads;
    const GenerateReport report = runDataset(sc, &traj, std::move(sensors), options);
    EXPECT_EQ(report.threads, threads);
    EXPECT_EQ(report.render_threads, threads) << "threads that rendered";
    EXPECT_EQ(gauge->peak.load(), threads) << "renders running at once";
    const std::string bytes = snapshot(options.out);
    if (reference.empty())
      reference = bytes;
    EXPECT_EQ(bytes, reference) << threads << " threads";
    fs::remove_all(options.out);
  }
}

scenario::Scenario twoImus() {
  return scenario::Scenario::resolve(
      {{"route", {{"generator", {{"length_m", 1500}}}}},
       {"sensors", {{"imus", {{{"preset", "consumer"}}, {{"preset", "consumer"}}}}}}},
      scenarioSchema());
}

TEST(SensorNames, UnnamedSensorsOfAKindGetUniqueNamesFilesAndNoise) {
  const scenario::Scenario sc = twoImus();
  EXPECT_EQ(sc.get<std::string>("sensors.imus[0].name"), "imu");
  EXPECT_EQ(sc.get<std::string>("sensors.imus[1].name"), "imu_1");
  GenerateOptions options;
  options.out = freshDir("two-imus");
  generate(sc, options);
  const std::string a = io::readFile(options.out / "sequences/00/imu.csv");
  const std::string b = io::readFile(options.out / "sequences/00/imu_1.csv");
  const std::string a_truth = io::readFile(options.out / "sequences/00/imu_truth.csv");
  const std::string b_truth = io::readFile(options.out / "sequences/00/imu_1_truth.csv");
  // Same mount: the same truth, but each IMU its own noise.
  EXPECT_EQ(a_truth.substr(0, a_truth.find("bias")), b_truth.substr(0, b_truth.find("bias")));
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), std::count(b.begin(), b.end(), '\n'));
  std::istringstream la(a), lb(b);
  std::string ra, rb;
  int rows = 0, differ = 0;
  std::getline(la, ra);
  std::getline(lb, rb);
  EXPECT_EQ(ra, rb);  // one header each
  while (std::getline(la, ra) && std::getline(lb, rb)) {
    ++rows;
    differ += ra.substr(ra.find(',')) != rb.substr(rb.find(','));
  }
  EXPECT_GT(rows, 100);
  EXPECT_EQ(differ, rows);
  fs::remove_all(options.out);
}

TEST(SensorNames, ClashesAndUnsafeNamesAreBadInputNamingBothPaths) {
  auto problems = [](const scenario::Json& sensors) {
    return scenarioSchema().resolve({{"sensors", sensors}}).problems;
  };
  const auto clash = problems({{"imus", {{{"name", "a"}}}}, {"odometers", {{{"name", "a"}}}}});
  ASSERT_EQ(clash.size(), 1u);
  EXPECT_EQ(clash[0].path, "sensors.odometers[0].name");
  EXPECT_NE(clash[0].message.find("sensors.imus[0]"), std::string::npos) << clash[0].message;
  for (const char* bad : {"../x", "/abs/x", "a/b", ".hidden", "", "x\\y"}) {
    const auto p = problems({{"gnss_receivers", {{{"name", bad}}}}});
    ASSERT_EQ(p.size(), 1u) << bad;
    EXPECT_EQ(p[0].path, "sensors.gnss_receivers[0].name");
  }
  // A name whose files collide with another sensor's: imu "x" writes x_truth.csv.
  const auto files =
      problems({{"imus", {{{"name", "x"}}}}, {"gnss_receivers", {{{"name", "x_truth"}}}}});
  ASSERT_EQ(files.size(), 1u);
  EXPECT_NE(files[0].message.find("x_truth.csv"), std::string::npos);
}

}  // namespace
}  // namespace trainsim::sim
