#include "trainsim/scenario/binding.hpp"

#include <fmt/format.h>

#include <string>

namespace trainsim::scenario {

double jsonDefault(double si_value, const Unit& unit) {
  const double v = unit.fromSi(si_value);
  if (!std::isfinite(v) || v == 0.0)
    return v;
  return std::stod(fmt::format("{:.12g}", v));
}

}  // namespace trainsim::scenario
