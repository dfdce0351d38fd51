#include "trainsim/sim/generate.hpp"

#include <fmt/format.h>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/version.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/frame_clock.hpp"
#include "trainsim/sim/movement.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

io::Manifest manifest(const scenario::Scenario& scenario, const io::DatasetLayout& layout,
                      const Trajectory* trajectory, const GenerateReport& report) {
  io::Manifest m;
  for (const auto& o : report.outputs) {
    m.sensors.push_back({o.name, o.kind, o.readings, o.files});
    if (o.kind == FrameClock::kKind)
      m.frames = o.readings;
  }
  m.version = std::string(version());
  m.scenario_hash = scenario.hash();
  m.seed = scenario.seed();
  m.sequence = layout.sequenceName();
  m.sequence_dir = layout.sequenceDir().generic_string();
  m.sample_period_ns = trajectorySection().read(scenario.json()).sample_period_ns;
  m.samples = trajectory ? trajectory->sampleCount() : 0;
  m.not_simulated = report.not_run;
  return m;
}

}  // namespace

GenerateReport runDataset(const scenario::Scenario& scenario, const Trajectory* trajectory,
                          std::vector<std::unique_ptr<Sensor>> sensors,
                          const GenerateOptions& options, std::vector<std::string> not_run,
                          const std::function<void(io::DatasetWriter&)>& write_plan) {
  GenerateReport report;
  report.not_run = std::move(not_run);
  const DatasetConfig dataset = datasetSection().read(scenario.json());
  const io::DatasetLayout layout(dataset.sequence);
  io::DatasetWriter writer(options.out, layout, {scenario.hash(), scenario.seed()}, options.policy);
  if (writer.start() == io::DatasetWriter::Start::kAlreadyComplete) {
    report.already_complete = true;
    return report;
  }
  writer.writeFile(io::DatasetLayout::kScenario, scenario.text());
  if (write_plan)
    write_plan(writer);

  if (trajectory != nullptr) {
    const TimeNs frame_period = dataset.frame_period_ns;
    sensors.insert(sensors.begin(), std::make_unique<FrameClock>(frame_period, *trajectory));
    MovementOptions movement;
    movement.checkpoint_every_samples = frame_period / trajectory->samplePeriod();
    movement.threads = options.threads;
    movement.progress = options.progress;
    movement.cancel = options.cancel;
    const MovementReport run = runMovement(*trajectory, sensors, writer, movement);
    for (std::size_t i = 0; i < sensors.size(); ++i) {
      std::vector<std::string> files;
      for (const std::string& f : sensors[i]->outputs())
        files.push_back(layout.inSequence(f).generic_string());
      report.outputs.push_back({sensors[i]->name(), sensors[i]->kind(), run.readings[i], files});
    }
    report.threads = run.threads;
    report.render_threads = run.render_threads;
    report.samples = trajectory->sampleCount();
  }
  writer.finish(manifest(scenario, layout, trajectory, report).toJson());
  return report;
}

GenerateReport generate(const scenario::Scenario& scenario, const GenerateOptions& options) {
  // Pipeline stages (docs/REFERENCES.md P1) that are not built yet, from the stage table; the
  // manifest and the CLI report them, so no run pretends.
  std::vector<std::string> not_run = stagesNotRun();
  // The output folder is judged before the plan, so a bad --out costs nothing.
  if (io::checkOutputFolder(options.out, options.policy, {scenario.hash(), scenario.seed()}) ==
      io::OutputFolder::kComplete) {
    GenerateReport report;
    report.already_complete = true;
    return report;
  }
  const CancelScope cancel(options.cancel);
  const std::unique_ptr<Plan> plan = makePlan(scenario);
  const SensorContext context =
      makeSensorContext(scenario, plan->trajectory(), &plan->route().route, &plan->layout());
  std::vector<std::unique_ptr<Sensor>> sensors = createSensors(context);
  return runDataset(scenario, &plan->trajectory(), std::move(sensors), options, std::move(not_run),
                    [&](io::DatasetWriter& writer) { writePlan(*plan, writer.root()); });
}

}  // namespace trainsim::sim
