#pragma once

#include <string_view>

namespace trainsim {
/// The TrainSim version, "MAJOR.MINOR.PATCH" (from the top-level CMake project).
std::string_view version();
}  // namespace trainsim
