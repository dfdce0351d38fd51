#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "trainsim/core/progress.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/sensor.hpp"
#include "trainsim/sim/trajectory.hpp"

namespace trainsim::sim {

struct GenerateOptions {
  std::filesystem::path out = "output";
  io::OutputPolicy policy;
  int threads = 0;  ///< 0: all cores. Never changes the output, only the speed.
  ProgressReporter* progress = nullptr;
  const std::atomic<bool>* cancel = nullptr;
};

/// What a run produced, for the CLI's and the studio's summaries.
struct GenerateReport {
  bool already_complete = false;  ///< --resume on a finished dataset: nothing was done
  std::int64_t samples = 0;       ///< trajectory samples simulated
  struct Output {
    std::string name;
    std::string kind;
    std::int64_t readings;
    std::vector<std::string> files;  ///< relative to the dataset root
    nlohmann::json summary;          ///< Sensor::summary()
  };
  std::vector<Output> outputs;
  int threads = 0;         ///< worker threads of the run loop
  int render_threads = 0;  ///< of which actually rendered readings
  /// Pipeline stages that did not run because they are not built yet, with the reason.
  std::vector<std::string> not_run;
};

/// Generates the dataset of a resolved scenario into options.out: every pipeline stage that
/// exists, in order (docs/REFERENCES.md P1). Throws ConfigError for unusable input or output
/// folders, IoError and RuntimeError for failures while running, Cancelled on request. On
/// failure the folder holds only complete frames and can be resumed.
GenerateReport generate(const scenario::Scenario& scenario, const GenerateOptions& options);

/// The run stage alone on a given trajectory with the given sensors (plus the frame clock):
/// opens the dataset folder, writes scenario.json, runs the movement system and writes the
/// manifest; `write_plan`, when given, writes the plan's files after scenario.json.
/// generate() calls it with the planned trajectory; tests call it with synthetic trajectories
/// and sensors.
GenerateReport runDataset(const scenario::Scenario& scenario, const Trajectory* trajectory,
                          std::vector<std::unique_ptr<Sensor>> sensors,
                          const GenerateOptions& options, std::vector<std::string> not_run = {},
                          const std::function<void(io::DatasetWriter&)>& write_plan = {});

}  // namespace trainsim::sim
