#include "trainsim/scenario/binding.hpp"

#include <fmt/format.h>

#include <string>

namespace trainsim::scenario {

double jsonDefault(double value_si, const Unit& unit) {
  const double v = unit.fromSi(value_si);
  if (!std::isfinite(v) || v == 0.0)
    return v;
  return std::stod(fmt::format("{:.12g}", v));
}

}  // namespace trainsim::scenario
