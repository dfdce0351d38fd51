// Position evaluation on transition curves: quadrature tolerance vs. error vs. time.
//
// Error is measured against the Fresnel power series (clothoid from a straight), evaluated in
// long double to convergence. Time per evaluation is given absolute and as a ratio to the
// closed-form arc evaluation measured in the same run (the cheapest possible element).

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "../tests/support/fresnel_series.hpp"
#include "trainsim/track/horizontal.hpp"

namespace {

using trainsim::track::HorizontalAlignment;
using trainsim::track::HorizontalElement;

template <typename F>
double nsPerCall(F&& f, int calls) {
  const auto t0 = std::chrono::steady_clock::now();
  double sink = 0;
  for (int i = 0; i < calls; ++i)
    sink += f(i);
  const auto t1 = std::chrono::steady_clock::now();
  if (sink == 42.0)
    fmt::print(" ");  // keep the loop
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / calls;
}

}  // namespace

int main() {
  constexpr int kCalls = 200'000;
  struct Case {
    const char* what;
    double r, l;
  };
  // A sharp but realistic transition (0.2 rad), and a stress case turning 2 rad in one element
  // (no railway has one; it shows where the adaptive subdivision starts to work).
  for (const Case c :
       {Case{"sharp transition", 300.0, 120.0}, Case{"stress: 2 rad", 100.0, 400.0}}) {
    const HorizontalAlignment arc({0, 0}, 0.0, {HorizontalElement::arc(c.l, c.r)});
    const double base =
        nsPerCall([&](int i) { return arc.at(c.l * (i % 997) / 997.0).position_m.x(); }, kCalls);
    fmt::print("\n{}: clothoid to R = {} m over L = {} m; error vs. Fresnel series\n", c.what, c.r,
               c.l);
    fmt::print("baseline: closed-form arc evaluation {:.1f} ns\n\n", base);
    fmt::print("| tolerance (m) | max error (m) | ns / evaluation | x arc baseline |\n");
    fmt::print("|---|---|---|---|\n");
    for (double tol : {1e-3, 1e-6, 1e-9, 1e-12}) {
      const HorizontalAlignment a({0, 0}, 0.0, {HorizontalElement::transition(c.l, 0.0, 1.0 / c.r)},
                                  tol);
      double worst = 0;
      for (int i = 0; i <= 1000; ++i) {
        const double s = c.l * i / 1000.0;
        worst = std::max(
            worst,
            (a.at(s).position_m - trainsim::testing::clothoidFresnelSeries(s, c.r * c.l)).norm());
      }
      const double ns =
          nsPerCall([&](int i) { return a.at(c.l * (i % 997) / 997.0).position_m.x(); }, kCalls);
      fmt::print("| {:.0e} | {:.2e} | {:.1f} | {:.2f} |\n", tol, worst, ns, ns / base);
    }
  }
  return 0;
}
