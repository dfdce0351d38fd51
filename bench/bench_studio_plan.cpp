// How long the studio takes to show a plan after an edit, against the plan itself.
//
// The studio re-plans off the GUI thread after every edit (PlanService). Its own cost on top
// of sim::makePlan (the baseline, measured in the same run) is buildSnapshot: polylines split
// by block type, violation and chainage marks, and the trajectory series for the plots (at
// most ~20 000 samples). Printed for the default 6 km route and longer generated routes.

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>

#include "plan_service.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace {

using Clock = std::chrono::steady_clock;

template <typename F>
double bestOf(int runs, F&& f) {
  double best = 1e300;
  for (int i = 0; i < runs; ++i) {
    const auto a = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - a).count());
  }
  return best;
}

}  // namespace

int main() {
  using namespace trainsim;
  fmt::print("{:>10} {:>14} {:>16} {:>8}\n", "route km", "makePlan ms", "buildSnapshot ms",
             "ratio");
  for (double km : {6.0, 30.0, 100.0}) {
    scenario::Json input = sim::loadScenario("").json();
    input["route"]["generator"]["length_m"] = km * 1000.0;
    const auto sc = scenario::Scenario::resolve(input, sim::scenarioSchema());
    const int runs = km > 50 ? 2 : 5;
    const double plan = bestOf(runs, [&] { (void)sim::makePlan(sc); });
    const double snap = bestOf(runs, [&] {
      sim::Planner fresh;
      (void)studio::buildSnapshot(sc, fresh);
    });
    fmt::print("{:>10.0f} {:>14.1f} {:>16.1f} {:>8.2f}\n", km, plan * 1e3, snap * 1e3, snap / plan);
  }
}
