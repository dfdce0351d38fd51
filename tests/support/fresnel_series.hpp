#pragma once

// Independent reference for clothoid positions, shared by the alignment tests and benchmark:
// the Fresnel power series of a clothoid that starts straight (κ0 = 0) at the origin heading
// east, with A² = R·L, summed in long double:
//   x = Σ (-1)^n s^(4n+1) / ((4n+1) (2n)!   (2A²)^(2n))
//   y = Σ (-1)^n s^(4n+3) / ((4n+3) (2n+1)! (2A²)^(2n+1))
// 14 terms converge to double precision for s²/(2A²) up to about 2 rad.

#include <cmath>

#include <Eigen/Core>

namespace trainsim::testing {

inline Eigen::Vector2d clothoidFresnelSeries(double s, double a2) {
  long double x = 0, y = 0, factorial_even = 1;  // (2n)!
  for (int n = 0; n < 14; ++n) {
    if (n > 0) {
      factorial_even *= (2.0L * n - 1) * (2.0L * n);
    }
    const long double factorial_odd = factorial_even * (2.0L * n + 1);  // (2n+1)!
    const long double sign = n % 2 == 0 ? 1.0L : -1.0L;
    x += sign * std::pow(static_cast<long double>(s), 4 * n + 1) /
         ((4 * n + 1) * factorial_even * std::pow(2.0L * a2, 2 * n));
    y += sign * std::pow(static_cast<long double>(s), 4 * n + 3) /
         ((4 * n + 3) * factorial_odd * std::pow(2.0L * a2, 2 * n + 1));
  }
  return {static_cast<double>(x), static_cast<double>(y)};
}

}  // namespace trainsim::testing
