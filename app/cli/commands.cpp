#include "commands.hpp"

#include <fmt/format.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/core/progress.hpp"
#include "trainsim/evaluation/odometry.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::cli {
namespace {

int g_exit_code = kExitOk;
std::atomic<bool> g_cancel{false};

// The first Ctrl-C or SIGTERM asks the run to stop at the next check (it then removes or keeps
// what it wrote, as the folder rules say); a second one kills at once.
extern "C" void onInterrupt(int signal) {
  g_cancel.store(true);
  std::signal(signal, SIG_DFL);
}

void catchInterrupts() {
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

struct CommonOptions {
  std::string scenario;  // empty: built-in default
  std::string log_level = "info";
};

struct PlanArgs : CommonOptions {
  std::string out;
  bool force = false;
  bool scene = false;
  double scene_from_m = 0.0;
  double scene_to_m = 1000.0;
};

struct EvaluateArgs {
  std::string gt, est, calib, times;
  double speed_bin_m_s = evaluation::EvaluateOptions{}.speed_bin_m_s;
  std::vector<double> lengths = evaluation::EvaluateOptions{}.lengths_m;
  std::size_t step = evaluation::EvaluateOptions{}.step;
  double eod_from_m = evaluation::EvaluateOptions{}.eod_from_m;
  bool json = false;
};

struct GenerateArgs : CommonOptions {
  std::string out = "output";
  std::optional<std::string> seed;  // parsed by seedOption(): CLI11 wraps "-1" to 2^64 - 1
  int threads = 0;
  bool resume = false;
  bool force = false;
  std::string progress = "auto";
};

void addLogLevel(CLI::App* cmd, std::string& level) {
  cmd->add_option("--log-level", level, "debug, info, warn, error or off")->capture_default_str();
}

void applyLogLevel(const std::string& level) {
  setLogLevel(parseLogLevel(level, "--log-level"));
}

std::string describeSource(const std::string& path) {
  return path.empty() ? "built-in default scenario" : path == "-" ? "standard input" : path;
}

// --seed as typed: a whole number within the scenario's seed range, refused naming the option
// (as the scenario would refuse it, but said of the command line, not of the file).
std::optional<std::uint64_t> seedOption(const std::optional<std::string>& text) {
  if (!text)
    return std::nullopt;
  const std::string& s = *text;
  const std::size_t sign = !s.empty() && s[0] == '-' ? 1 : 0;
  if (s.size() == sign || !std::all_of(s.begin() + static_cast<std::ptrdiff_t>(sign), s.end(),
                                       [](char c) { return c >= '0' && c <= '9'; }))
    throw ConfigError(fmt::format("--seed: '{}' is not a whole number", s));
  const double max = scenario::seedParam().maximum.value();
  std::uint64_t seed = 0;
  const auto [at, ec] = std::from_chars(s.data() + sign, s.data() + s.size(), seed);
  if (sign == 1 && (seed != 0 || ec != std::errc()))
    throw ConfigError(fmt::format("--seed: {} is below the minimum 0", s));
  if (ec != std::errc() || static_cast<double>(seed) > max)
    throw ConfigError(fmt::format("--seed: {} is above the maximum {:.0f}", s, max));
  return seed;
}

void runGenerate(const GenerateArgs& args) {
  catchInterrupts();
  applyLogLevel(args.log_level);
  if (args.threads < 0) {
    throw ConfigError(fmt::format("--threads: {} is below the minimum 0", args.threads));
  }
  const scenario::Scenario scenario = sim::loadScenario(args.scenario, seedOption(args.seed));
  ProgressReporter progress(parseProgressMode(args.progress));
  sim::GenerateOptions options;
  options.out = args.out;
  options.policy = {args.force, args.resume};
  options.threads = args.threads;
  options.progress = &progress;
  options.cancel = &g_cancel;

  logInfo(fmt::format("generate: {} (scenario {}, seed {}) into {}", describeSource(args.scenario),
                      scenario.hash(), scenario.seed(), args.out));
  const sim::GenerateReport report = sim::generate(scenario, options);
  if (report.already_complete) {
    logInfo(
        fmt::format("{} already holds the complete dataset of this scenario and seed; "
                    "nothing to do",
                    args.out));
    return;
  }
  if (report.outputs.empty()) {
    logInfo("sensors run: none");
  }
  for (const auto& o : report.outputs) {
    logInfo(fmt::format("sensor {} ({}): {} readings", o.name, o.kind, o.readings));
  }
  if (report.threads > 0)
    logInfo(fmt::format("run loop: {} worker threads, {} of them rendered readings", report.threads,
                        report.render_threads));
  for (const auto& stage : report.not_run) {
    logWarn("not simulated yet: " + stage);
  }
  logInfo(fmt::format("wrote {}/manifest.json and {}/scenario.json", args.out, args.out));
}

void runPlan(const PlanArgs& args) {
  catchInterrupts();
  applyLogLevel(args.log_level);
  const scenario::Scenario scenario = sim::loadScenario(args.scenario);
  if (args.scene && args.scene_to_m <= args.scene_from_m)
    throw ConfigError(fmt::format("--scene-to: {} m must lie beyond --scene-from ({} m)",
                                  args.scene_to_m, args.scene_from_m));
  io::checkOutputFolder(args.out, {args.force, false});  // before the plan, not after it
  const CancelScope cancel(&g_cancel);
  const std::unique_ptr<sim::Plan> plan = sim::makePlan(scenario);
  // A window past the route's end would write no tile of it (one ending past it is cut there).
  const auto& blocks = plan->route().route.blocks;
  const double route_end = blocks.empty() ? 0.0 : blocks.back().chainage_end_m;
  if (args.scene && args.scene_from_m >= route_end)
    throw ConfigError(fmt::format("--scene-from: {} m lies at or beyond the route's end ({:.0f} m)",
                                  args.scene_from_m, route_end));
  sim::writePlanFolder(*plan, scenario, args.out, args.force);
  logInfo(
      fmt::format("wrote {0}/scenario.json, {0}/railroad.json, {0}/trajectory.csv and "
                  "{0}/design_report.json",
                  args.out));
  if (!args.scene)
    return;
  const std::filesystem::path scene_dir =
      std::filesystem::path(args.out) / io::DatasetLayout::kScene;
  try {
    const auto environment = sim::makeEnvironment(*plan, scenario);
    sim::writeScene(*environment, scene_dir, {args.scene_from_m, args.scene_to_m});
  } catch (...) {
    std::error_code ignored;  // no half-written scene stays
    std::filesystem::remove_all(scene_dir, ignored);
    throw;
  }
  logInfo(fmt::format("wrote {}/terrain/, {}/objects.csv and {}/scene.vtm", scene_dir.string(),
                      scene_dir.string(), scene_dir.string()));
}

// Everything a run reads and checks before it writes: the scenario, the files it names, the
// route with its design rules and the layout and motion built on it. Exit 0 means `plan` and
// `generate` will not fail on their input.
void runValidate(const std::string& path) {
  catchInterrupts();
  const CancelScope cancel(&g_cancel);
  try {
    const scenario::Scenario scenario = sim::loadScenario(path);
    setLogLevel(LogLevel::kWarn);  // the plan's summary line is not validate's to print
    const std::unique_ptr<sim::Plan> plan = sim::makePlan(scenario);
    // What generate would say as its run starts, said now: of the obstacles where they stand
    // (the environment places them; its tiles are made only when a sensor asks for them) and of
    // the sensors' settings.
    if (sim::needsScene(scenario.json()))
      sim::makeEnvironment(*plan, scenario);
    const std::vector<std::string> warnings = sim::sensorWarnings(scenario.json());
    for (const std::string& line : warnings)
      logWarn(line);
    std::cout << fmt::format(
        "{}: valid ({:.0f} m route, {} tracks, {:.0f} s run, {} design-rule warnings, {} sensor "
        "warnings)\n",
        describeSource(path), plan->route().route.track.length(), plan->layout().tracks.size(),
        plan->motion().duration(), plan->violations().size(), warnings.size());
  } catch (const scenario::InvalidScenario& e) {
    for (const auto& p : e.problems()) {
      std::cerr << e.source() << ": " << p.text() << "\n";
    }
    g_exit_code = kExitInvalidInput;
  } catch (const ConfigError& e) {  // unreadable file, malformed JSON, a route that cannot be
    std::cerr << e.what() << "\n";  // built: one line already
    g_exit_code = kExitInvalidInput;
  }
}

// Odometry metrics of an estimate against the ground truth, both KITTI poses files: the
// devkit's segment errors and the paper's TEX, TEY and EOD, on standard output.
void runEvaluate(const EvaluateArgs& args) {
  const evaluation::Poses gt = evaluation::readKittiPoses(args.gt);
  const evaluation::Poses est = evaluation::readKittiPoses(args.est);
  std::optional<evaluation::Pose> tr;
  if (!args.calib.empty())
    tr = evaluation::readKittiTr(args.calib);
  evaluation::EvaluateOptions options;
  options.lengths_m = args.lengths;
  options.step = args.step;
  options.eod_from_m = args.eod_from_m;
  options.tr = tr ? &*tr : nullptr;
  std::vector<double> times;
  if (!args.times.empty())
    times = evaluation::readKittiTimes(args.times);
  options.times = times;
  options.speed_bin_m_s = args.speed_bin_m_s;
  const evaluation::Report report = evaluation::evaluate(gt, est, options);
  std::cout << (args.json ? evaluation::json(report) : evaluation::markdown(report));
}

// `trainsim bench`: the project's benchmarks (bench/), each a program built beside trainsim,
// run one after another with their tables on standard output. They stay separate programs
// because each links what it measures (Embree, VTK, the studio) and `make bench` runs them the
// same way; --quick runs the run-time-against-error tables of the fidelity knobs on the default
// scene only.
void runBench(bool quick) {
  struct Bench {
    const char* name;
    std::vector<std::string> quick_args;  // what --quick passes it
    bool in_quick;
  };
  const std::vector<Bench> benches = {
      {"bench_alignment", {}, true},        // quadrature tolerance → position error → time
      {"bench_imu", {}, true},              // the IMU's error chain: samples per second
      {"bench_lidar", {"--quick"}, true},   // frame against raw traversal; sub-rays → wire hits
      {"bench_camera", {"--quick"}, true},  // ms per frame: culling, level of detail, PNG
      {"bench_environment", {"--quick"}, true},
      {"bench_route", {}, false},
      {"bench_run_loop", {}, false},
      {"bench_plan_memory", {}, false},
      {"bench_studio_plan", {}, false},
  };
  const std::filesystem::path dir = std::filesystem::read_symlink("/proc/self/exe").parent_path();
  int ran = 0;
  for (const Bench& b : benches) {
    if (quick && !b.in_quick)
      continue;
    const std::filesystem::path program = dir / b.name;
    if (!std::filesystem::exists(program)) {
      logWarn(fmt::format("bench: {} is not built (it needs the part of TrainSim it measures)",
                          program.string()));
      continue;
    }
    std::vector<std::string> args = {program.string()};
    if (quick)
      args.insert(args.end(), b.quick_args.begin(), b.quick_args.end());
    std::vector<char*> argv;
    for (std::string& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    std::cout << fmt::format("\n## {}{}\n", b.name,
                             quick && !b.quick_args.empty() ? " --quick" : "")
              << std::flush;
    pid_t pid = 0;
    if (const int e = posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ); e != 0)
      throw RuntimeError(systemErrorMessage("bench: cannot start", program.string(), e));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      throw RuntimeError(fmt::format("bench: {} failed ({})", b.name,
                                     WIFEXITED(status)
                                         ? fmt::format("exit {}", WEXITSTATUS(status))
                                         : fmt::format("signal {}", WTERMSIG(status))));
    ++ran;
  }
  if (ran == 0)
    throw RuntimeError(fmt::format(
        "bench: no benchmark program beside {}: they are built with the project (make build)",
        dir.string()));
}

}  // namespace

int commandExitCode() {
  return g_exit_code;
}

void addCommands(CLI::App& app) {
  app.require_subcommand(1);

  // generate
  static GenerateArgs gen;
  CLI::App* generate = app.add_subcommand(
      "generate",
      "Run the whole pipeline and write a dataset (built-in default scenario when "
      "SCENARIO is omitted; '-' reads standard input)");
  generate->add_option("SCENARIO", gen.scenario, "Scenario JSON file");
  generate->add_option("--out,-o", gen.out, "Output folder")->capture_default_str();
  generate->add_option("--seed", gen.seed, "Replace the scenario's seed");
  generate
      ->add_option("--threads", gen.threads,
                   "Worker threads, 0 for all cores (never "
                   "changes the output)")
      ->capture_default_str();
  generate->add_flag("--resume", gen.resume, "Continue an interrupted run in --out");
  generate->add_flag("--force", gen.force,
                     "Start over in a non-empty --out (removes only TrainSim's own entries)");
  generate
      ->add_option("--progress", gen.progress,
                   "auto (a bar on a terminal), bar, json (one line per update on "
                   "standard output) or none")
      ->capture_default_str();
  addLogLevel(generate, gen.log_level);
  generate->callback([] { runGenerate(gen); });

  // plan
  static PlanArgs plan;
  CLI::App* plan_cmd = app.add_subcommand(
      "plan", "Plan route, layout, trajectory, terrain and objects with the design-rule report");
  plan_cmd->add_option("SCENARIO", plan.scenario, "Scenario JSON file (default: built-in)");
  plan_cmd->add_option("--out,-o", plan.out, "Output folder")->required();
  plan_cmd->add_flag("--force", plan.force,
                     "Write into a non-empty --out (removes only TrainSim's own entries)");
  CLI::Option* scene_flag =
      plan_cmd->add_flag("--scene", plan.scene,
                         "Also write the scene: terrain tiles (16-bit PNG + JSON), objects.csv and "
                         "scene.vtm for ParaView");
  plan_cmd
      ->add_option("--scene-from", plan.scene_from_m,
                   "Main chainage (m) where scene.vtm's window starts (with --scene)")
      ->check(CLI::Range(0.0, 1e7))
      ->needs(scene_flag);
  plan_cmd
      ->add_option("--scene-to", plan.scene_to_m,
                   "Main chainage (m) where it ends, cut at the route's end (with --scene)")
      ->check(CLI::Range(0.0, 1e7))
      ->needs(scene_flag);
  addLogLevel(plan_cmd, plan.log_level);
  plan_cmd->callback([] { runPlan(plan); });

  // validate
  static std::string validate_path;
  CLI::App* validate = app.add_subcommand(
      "validate",
      "Check a scenario and everything a run reads (waypoint file, route, design rules, layout, "
      "motion): exit 0 when plan and generate will accept it, 2 with one line per problem");
  validate->add_option("SCENARIO", validate_path, "Scenario JSON file, '-' for standard input")
      ->required();
  validate->callback([] { runValidate(validate_path); });

  // evaluate
  static EvaluateArgs evaluate;
  CLI::App* evaluate_cmd = app.add_subcommand(
      "evaluate",
      "Odometry metrics of an estimated trajectory against the ground truth (KITTI poses "
      "files): the KITTI devkit's segment errors and the TrainSim paper's TEX, TEY and EOD");
  evaluate_cmd->add_option("--gt", evaluate.gt, "Ground-truth poses (a dataset's poses.txt)")
      ->required();
  evaluate_cmd->add_option("--est", evaluate.est, "Estimated poses, one line per frame")
      ->required();
  evaluate_cmd->add_option("--calib", evaluate.calib,
                           "calib.txt: TEX, TEY and EOD in the velodyne's axes (its Tr), not "
                           "camera 0's renamed");
  evaluate_cmd->add_option("--times", evaluate.times,
                           "times.txt: the segment errors by speed as well (the ground truth's "
                           "path over the time it took)");
  evaluate_cmd
      ->add_option("--speed-bin", evaluate.speed_bin_m_s, "Width of the speed table's bins (m/s)")
      ->capture_default_str();
  evaluate_cmd
      ->add_option("--lengths", evaluate.lengths,
                   "Segment lengths (m), comma-separated; the devkit's by default")
      ->delimiter(',')
      ->capture_default_str();
  evaluate_cmd->add_option("--step", evaluate.step, "Frames between segment starts")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000'000}))
      ->capture_default_str();
  evaluate_cmd
      ->add_option("--eod-from", evaluate.eod_from_m,
                   "Path length (m) from which EOD is counted (near the start it divides by "
                   "next to nothing)")
      ->capture_default_str();
  evaluate_cmd->add_flag("--json", evaluate.json, "One JSON object instead of Markdown tables");
  evaluate_cmd->callback([] { runEvaluate(evaluate); });

  // bench
  static bool bench_quick = false;
  CLI::App* bench = app.add_subcommand(
      "bench",
      "Run the benchmarks: run time against error for the main fidelity knobs, each as a ratio "
      "to a baseline measured in the same run (docs/PERFORMANCE.md)");
  bench->add_flag("--quick", bench_quick,
                  "The fidelity knobs' tables on the default scene only (a few minutes)");
  bench->callback([] { runBench(bench_quick); });

  // defaults
  app.add_subcommand("defaults", "Print the built-in default scenario with every parameter")
      ->callback([] { std::cout << sim::loadScenario("").text(); });

  // schema
  app.add_subcommand("schema", "Print the parameter table (Markdown, as in docs/SCENARIO.md)")
      ->callback([] { std::cout << sim::scenarioSchema().markdown(sim::defaultScenarioText()); });
}

}  // namespace trainsim::cli
