// trainsim-synthetic-run: the dataset run stage on a synthetic trajectory with test sensors,
// through the same code path as `trainsim generate` (sim::runDataset). Used by the kill -9 /
// --resume and disk-full integration tests until real sensors exist.
//
//   trainsim-synthetic-run OUT [--samples N] [--delay-ms D] [--payload BYTES] [--resume] [--force]

#include <CLI/CLI.hpp>

#include <iostream>

#include "synthetic.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/schema.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Synthetic dataset run for tests"};
  std::string out;
  std::int64_t samples = 300;
  int delay_ms = 0;
  std::size_t payload = 4096;
  bool resume = false, force = false;
  app.add_option("OUT", out)->required();
  app.add_option("--samples", samples);
  app.add_option("--delay-ms", delay_ms);
  app.add_option("--payload", payload);
  app.add_flag("--resume", resume);
  app.add_flag("--force", force);
  CLI11_PARSE(app, argc, argv);
  try {
    // The schema's defaults (frames every 100 ms), not the showcase scenario.
    const auto scenario = trainsim::scenario::Scenario::resolve(trainsim::scenario::Json::object(),
                                                                trainsim::sim::scenarioSchema());
    const auto ts = scenario.get<trainsim::TimeNs>("trajectory.sample_period_ns");
    const trainsim::testing::StraightTrajectory trajectory(ts, samples, 20.0, 0.3);
    std::vector<std::unique_ptr<trainsim::sim::Sensor>> sensors;
    sensors.push_back(std::make_unique<trainsim::testing::NoiseSensor>(trajectory, "noise_fast", ts,
                                                                       scenario.seed(), 64, 0));
    sensors.push_back(std::make_unique<trainsim::testing::NoiseSensor>(
        trajectory, "noise_frames", scenario.get<trainsim::TimeNs>("dataset.frame_period_ns"),
        scenario.seed(), payload, delay_ms));
    trainsim::sim::GenerateOptions options;
    options.out = out;
    options.policy = {force, resume};
    trainsim::sim::runDataset(scenario, &trajectory, std::move(sensors), options);
  } catch (const trainsim::Error& e) {
    std::cerr << "trainsim-synthetic-run: " << e.what() << "\n";
    return trainsim::exitCodeFor(e);
  }
  return 0;
}
