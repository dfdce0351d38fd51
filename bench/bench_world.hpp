#pragma once
// The default scenario's world for the benchmarks (its plan and its environment, with the
// route's length changed when asked) and their timing helpers.
#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::bench {

using Clock = std::chrono::steady_clock;

/// Milliseconds since t0.
inline double ms(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The q-quantile (0 ... 1) of `v`, by rank: the value with a share q of the others below it.
inline double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

/// The median of repeated timings.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct World {
  scenario::Scenario scenario;
  std::unique_ptr<sim::Plan> plan;
  std::shared_ptr<const sim::EnvironmentStage> stage;
};

/// The world of the default scenario with `changes` merged into it (JSON merge patch).
inline World makeWorldWith(const scenario::Json& changes) {
  scenario::Json input = scenario::Json::parse(sim::defaultScenarioText());
  input.merge_patch(changes);
  World w{sim::resolveScenario(input, "", "bench"), nullptr, nullptr};
  w.plan = sim::makePlan(w.scenario);
  w.stage = sim::makeEnvironment(*w.plan, w.scenario);
  return w;
}

/// The default scenario with a generated route of `length_m` (0: its own 6 km) and, when
/// `simplify_tolerance_m` is not negative, that terrain tolerance (0: the full height grid).
inline World makeWorld(double length_m, double simplify_tolerance_m = -1.0) {
  scenario::Json changes = scenario::Json::object();
  if (length_m > 0.0)
    changes["route"]["generator"]["length_m"] = length_m;
  if (simplify_tolerance_m >= 0.0)
    changes["terrain"]["simplify_tolerance_m"] = simplify_tolerance_m;
  return makeWorldWith(changes);
}

}  // namespace trainsim::bench
