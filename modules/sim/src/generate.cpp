#include "trainsim/sim/generate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

#include "classes_yaml.hpp"
#include "trainsim/camera/x_display.hpp"
#include "trainsim/core/cancel.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/version.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/frame_clock.hpp"
#include "trainsim/sim/instance_table.hpp"
#include "trainsim/sim/movement.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

io::Manifest manifest(const scenario::Scenario& scenario, const io::DatasetLayout& layout,
                      const Trajectory* trajectory, const GenerateReport& report) {
  io::Manifest m;
  for (const auto& o : report.outputs) {
    m.sensors.push_back({o.name, o.kind, o.readings, o.files, o.summary});
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
  m.classes = nlohmann::json::array();
  for (const scene::SemanticClass& c : scene::classes())
    m.classes.push_back({{"id", c.id},
                         {"name", c.name},
                         {"colour", c.colour},
                         {"thing", c.thing},
                         {"semantickitti", c.semantickitti},
                         {"railsem19", c.railsem19},
                         {"osdar23", c.osdar23}});
  return m;
}

// Each class's points in the first LiDAR's summary, by class id (for classes.yaml's content,
// which SemanticKITTI's trainers weigh classes by); without a LiDAR, the first camera's
// semantic pixels; all 0 without either.
std::pair<std::vector<std::int64_t>, std::string> classContent(const GenerateReport& report) {
  std::vector<std::int64_t> counts(scene::classes().size(), 0);
  const std::tuple<const char*, const char*, const char*> sources[] = {
      {kLidarKind, "class_points", "the first LiDAR's points"},
      {kCameraKind, "class_pixels", "the first camera's semantic pixels (no LiDAR)"}};
  for (const auto& [kind, key, counted] : sources)
    for (const auto& o : report.outputs) {
      if (o.kind != kind || !o.summary.is_object() || !o.summary.contains(key))
        continue;
      for (const auto& [name, count] : o.summary.at(key).items())
        counts[scene::classId(name)] = count.get<std::int64_t>();
      if (std::any_of(counts.begin(), counts.end(), [](std::int64_t n) { return n > 0; }))
        return {counts, counted};
    }
  return {counts, "the first LiDAR's points"};
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
  // calib.txt in KITTI's order: P0, P1, … then Tr, Tr_1, … (readers that take lines by position
  // find them where KITTI has them), then what KITTI's odometry files lack (D2: a lens).
  std::vector<std::string> lines;
  for (const auto& sensor : sensors)
    for (const std::string& line : sensor->calibration())
      lines.push_back(line);
  // A camera-only run: KITTI's readers (pykitti's odometry loader) need a Tr, so the vehicle's
  // body frame (x forward, y left, z up: the axes a KITTI velodyne has) stands in for the
  // velodyne it does not have.
  const auto has = [&](std::string_view key) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& line) { return line.starts_with(key); });
  };
  if (has("P0:") && !has("Tr:"))
    lines.push_back(kittiCalibLine(
        "Tr", kittiTr(referenceCameraPose(scenario.json()), Eigen::Isometry3d::Identity())
                  .matrix()
                  .topRows<3>()));
  // A LiDAR-only run: KITTI's readers (pykitti's odometry loader) read P0–P3 as well, so they
  // are [I | 0]: camera 0's frame (the reference camera's axes at the body's reference point)
  // with a unit focal length, as there is no image to project into.
  if (has("Tr:") && !has("P0:"))
    for (int n = 0; n < 4; ++n)
      lines.push_back(
          kittiCalibLine(fmt::format("P{}", n), Eigen::Matrix<double, 3, 4>::Identity()));
  const auto rank = [](const std::string& line) {
    return line.starts_with("P")    ? std::stoi(line.substr(1))
           : line.starts_with("Tr") ? 1 << 20
                                    : 1 << 21;
  };
  std::stable_sort(lines.begin(), lines.end(),
                   [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
  std::string calib;
  for (const std::string& line : lines)
    calib += line + "\n";
  if (!calib.empty())
    writer.writeFile(layout.inSequence(io::DatasetLayout::kCalib), calib);

  if (trajectory != nullptr) {
    const TimeNs frame_period = dataset.frame_period_ns;
    sensors.insert(sensors.begin(),
                   std::make_unique<FrameClock>(frame_period, *trajectory,
                                                referenceCameraPose(scenario.json())));
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
      report.outputs.push_back(
          {sensors[i]->name(), sensors[i]->kind(), run.readings[i], files, sensors[i]->summary()});
    }
    report.threads = run.threads;
    report.render_threads = run.render_threads;
    report.samples = trajectory->sampleCount();
  }
  const auto [content, counted] = classContent(report);
  writer.writeFile(io::DatasetLayout::kClasses, classesYaml(content, layout.sequence(), counted));
  writer.finish(manifest(scenario, layout, trajectory, report).toJson());
  return report;
}

// Tiles the run's scene stream holds: the windows of the frames in flight (a 120 m LiDAR
// reaches into 4 scene tiles of 252 m, 9 at most; 2 × threads + 1 frames render at once,
// mostly over the same tiles).
constexpr std::size_t kSceneStreamTiles = 16;

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
  SensorContext context =
      makeSensorContext(scenario, plan->trajectory(), &plan->route().route, &plan->layout());
  context.cancel = options.cancel;
  // The environment, its scene stream and Embree's world exist only if a sensor needs them.
  std::shared_ptr<const EnvironmentStage> environment;
  std::unique_ptr<scene::SceneStream> stream;
  if (needsScene(scenario.json())) {
    environment = makeEnvironment(*plan, scenario);
    stream = environment->environment->stream(kSceneStreamTiles);
    context.scene = stream.get();
    // What instances.csv tells of an object: its track, a signal's aspect, and that a signal is
    // a signal even where its post is seen before its head.
    auto facts = [stage = environment](scene::InstanceId id) {
      const environment::Environment& env = *stage->environment;
      const auto aspect = env.signalAspect(id);
      if (!aspect)
        return InstanceTable::Facts{env.trackOf(id), {}, std::nullopt};
      return InstanceTable::Facts{env.trackOf(id), environment::signalAspectName(*aspect),
                                  scene::cls::kSignal};
    };
    context.instances = std::make_shared<InstanceTable>(std::move(facts));
  }
  if (hasSensors(scenario.json(), "lidars"))
    context.rays = std::make_shared<lidar::RayWorld>();
  // Cameras render through X: without a display, a private Xvfb for the run.
  std::unique_ptr<camera::XDisplay> display;
  if (hasSensors(scenario.json(), "cameras"))
    display = camera::XDisplay::ensure();
  std::vector<std::unique_ptr<Sensor>> sensors =
      scenario::namingItsSource(scenario, [&] { return createSensors(context); });
  GenerateReport report =
      runDataset(scenario, &plan->trajectory(), std::move(sensors), options, std::move(not_run),
                 [&](io::DatasetWriter& writer) { writePlan(*plan, writer.root()); });
  // A tile made more than once was dropped from the stream while the frames still needed it.
  if (stream)
    logDebug(fmt::format("scene: {} tiles made, of the {} along the route", stream->made(),
                         environment->environment->tiles().size()));
  return report;
}

}  // namespace trainsim::sim
