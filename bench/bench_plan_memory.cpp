// Peak memory of `trainsim plan` against the route's length: the built-in default scenario
// with a generated route of 10 km (the baseline, measured in the same run), 100 km and
// 1000 km, each planned by the real binary in a child process whose peak resident set size
// (getrusage of the child) is reported. The plan streams trajectory.csv and railroad.json
// and holds the layout as offset laws (polylines are sampled on demand), so the peak should
// stay flat: the acceptance bar is 1000 km <= 1.2 x 10 km.

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "trainsim/sim/schema.hpp"

namespace {

namespace fs = std::filesystem;

struct Peak {
  double mib = 0.0;
  double seconds = 0.0;
  std::uintmax_t trajectory_bytes = 0;
};

Peak planPeak(const fs::path& trainsim, const nlohmann::json& scenario, double length_m) {
  nlohmann::json sc = scenario;
  sc["route"]["source"] = "generated";
  sc["route"]["generator"]["length_m"] = length_m;
  sc["sensors"] = nlohmann::json::object();
  const fs::path dir =
      fs::temp_directory_path() / fmt::format("trainsim-bench-plan-{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "scenario.json";
  std::ofstream(file) << sc.dump();
  const fs::path out = dir / "plan";
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t child = ::fork();
  if (child == 0) {
    const std::string exe = trainsim.string(), in = file.string(), to = out.string();
    ::execl(exe.c_str(), exe.c_str(), "plan", in.c_str(), "--out", to.c_str(), "--log-level",
            "error", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  ::wait4(child, &status, 0, &usage);
  Peak p;
  p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print(stderr, "trainsim plan failed for {} m (status {})\n", length_m, status);
    std::exit(1);
  }
  p.mib = static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
  p.trajectory_bytes = fs::file_size(out / "trajectory.csv");
  fs::remove_all(dir);
  return p;
}

}  // namespace

int main() {
  const fs::path trainsim = fs::canonical("/proc/self/exe").parent_path() / "trainsim";
  if (!fs::exists(trainsim)) {
    fmt::print(stderr, "{} not found (build the trainsim target)\n", trainsim.string());
    return 1;
  }
  const nlohmann::json scenario = trainsim::sim::loadScenario("").json();
  fmt::print("trainsim plan, default scenario, generated route, 100 Hz trajectory\n");
  fmt::print("{:>10} {:>12} {:>10} {:>10} {:>14}\n", "route", "peak [MiB]", "ratio", "time [s]",
             "trajectory.csv");
  const Peak base = planPeak(trainsim, scenario, 10'000.0);
  const auto row = [&](double km, const Peak& p) {
    fmt::print("{:>7.0f} km {:>12.2f} {:>10.3f} {:>10.1f} {:>11.0f} MB\n", km, p.mib,
               p.mib / base.mib, p.seconds, static_cast<double>(p.trajectory_bytes) / 1e6);
  };
  row(10.0, base);
  row(100.0, planPeak(trainsim, scenario, 100'000.0));
  row(1000.0, planPeak(trainsim, scenario, 1'000'000.0));
  return 0;
}
