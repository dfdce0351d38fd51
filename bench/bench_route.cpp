// Generating a 100 km route and its 100 Hz trajectory: time and peak memory per stage.
//
// Stages: route generation (random route under the design rules), design-rule check, motion
// plan (jerk-limited speed profile), trajectory sampling (both bogies, body pose, closed-form
// rates at every sample). The baseline, measured in the same run, is evaluating the bare
// track centreline (Track::atDistance) at as many points as there are samples; the trajectory
// costs about two of those (one per bogie) plus the rigid-body algebra.

#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdint>

#include "trainsim/track/motion.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace

int main(int argc, char** argv) {
  using namespace trainsim::track;
  const double length_km = argc > 1 ? std::atof(argv[1]) : 100.0;
  const double period_s = 0.01;
  const double rss0 = peakRssMiB();

  const auto t0 = Clock::now();
  RouteGeneratorParams p;
  p.length_m = length_km * 1000.0;
  const RouteOptions options;
  const DesignedRoute route = generateRoute(p, options, 2026);
  const auto t1 = Clock::now();
  const std::size_t violations = checkDesign(route.route, options.rules).size();
  const auto t2 = Clock::now();
  const double u_end = route.route.track.distanceLength() - 1.0;
  const MotionProfile motion = planMotion(route.route, route.stops, {}, {}, 17.5, u_end);
  const auto t3 = Clock::now();
  const auto samples = static_cast<std::int64_t>(motion.duration() / period_s) + 1;
  double sink = 0.0;
  for (std::int64_t k = 0; k < samples; ++k) {
    const BodyState b = bodyState(route.route.track, {17.5}, motion.at(k * period_s));
    sink += b.w_body.z() + b.origin.x();
  }
  const auto t4 = Clock::now();
  // Baseline: the bare centreline at the same number of points.
  const double step = u_end / static_cast<double>(samples);
  for (std::int64_t k = 0; k < samples; ++k)
    sink += route.route.track.atDistance(static_cast<double>(k) * step).position.x();
  const auto t5 = Clock::now();

  const double base_ns = seconds(t4, t5) * 1e9 / static_cast<double>(samples);
  const double traj_ns = seconds(t3, t4) * 1e9 / static_cast<double>(samples);
  fmt::print("route {:.0f} km: {} horizontal elements, {} blocks, {} stops, {} violations\n",
             length_km, route.route.track.horizontal().elements().size(), route.route.blocks.size(),
             route.stops.size(), violations);
  fmt::print("run: {:.0f} s, {} samples at 100 Hz\n\n", motion.duration(), samples);
  fmt::print("| stage | time | per unit |\n|---|---|---|\n");
  fmt::print("| route generation | {:.2f} ms | {:.3f} ms/km |\n", seconds(t0, t1) * 1e3,
             seconds(t0, t1) * 1e3 / length_km);
  fmt::print("| design-rule check | {:.2f} ms | {:.3f} ms/km |\n", seconds(t1, t2) * 1e3,
             seconds(t1, t2) * 1e3 / length_km);
  fmt::print("| motion plan | {:.2f} ms | {} segments |\n", seconds(t2, t3) * 1e3,
             motion.segments().size());
  fmt::print("| trajectory sampling | {:.1f} ms | {:.0f} ns/sample = {:.2f} x baseline |\n",
             seconds(t3, t4) * 1e3, traj_ns, traj_ns / base_ns);
  fmt::print("| baseline: centreline only | {:.1f} ms | {:.0f} ns/point |\n", seconds(t4, t5) * 1e3,
             base_ns);
  fmt::print("\npeak RSS {:.1f} MiB (at start {:.1f} MiB){}\n", peakRssMiB(), rss0,
             sink == 0.123 ? " " : "");
  return 0;
}
