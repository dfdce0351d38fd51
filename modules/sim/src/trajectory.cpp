#include "trainsim/sim/trajectory.hpp"

#include <array>
#include <cmath>

namespace trainsim::sim {

void intervalNodes(const Trajectory& trajectory, TimeNs t0, TimeNs t1,
                   const std::function<void(TimeNs, double)>& node,
                   const std::function<void(TimeNs)>& breakpoint) {
  // Three-point Gauss–Legendre on [-1, 1]: nodes 0, ±sqrt(3/5), weights 8/9, 5/9.
  static const std::array<double, 3> x = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  static constexpr std::array<double, 3> w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  std::vector<TimeNs> cuts = trajectory.breakpoints(t0, t1);
  if (breakpoint)
    for (const TimeNs t : cuts)
      breakpoint(t);
  cuts.insert(cuts.begin(), t0);
  cuts.push_back(t1);
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = static_cast<double>(cuts[i]);
    const double half = 0.5 * static_cast<double>(cuts[i + 1] - cuts[i]);
    if (half <= 0.0)
      continue;
    for (std::size_t j = 0; j < 3; ++j)
      node(static_cast<TimeNs>(std::llround(a + half * (1.0 + x[j]))), w[j] * half * 1e-9);
  }
}

}  // namespace trainsim::sim
