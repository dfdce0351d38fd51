#pragma once

// Independent reference for long element chains, shared by the 1000 km precision tests:
// Simpson's rule in long double on each element's closed-form heading, one element at a time
// (so that the heading's kinks fall on grid points), with a step of about `step_m`.

#include <cmath>
#include <vector>

#include "trainsim/track/horizontal.hpp"

namespace trainsim::testing {

struct ChainEnd {
  long double x, y, heading;
};

inline ChainEnd simpsonChainEnd(const std::vector<track::HorizontalElement>& chain, long double x,
                                long double y, long double heading, double step_m) {
  for (const track::HorizontalElement& e : chain) {
    const int n = 2 * std::max(1, static_cast<int>(std::lround(e.length_m / (2 * step_m))));
    const long double h = static_cast<long double>(e.length_m) / n;
    long double sx = 0, sy = 0;
    for (int i = 0; i <= n; ++i) {
      const long double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      const long double t = heading + e.headingChange(static_cast<double>(i * h));
      sx += w * std::cos(t);
      sy += w * std::sin(t);
    }
    x += sx * h / 3;
    y += sy * h / 3;
    heading += e.headingChange(e.length_m);
  }
  return {x, y, heading};
}

}  // namespace trainsim::testing
