#pragma once

// Small text helpers shared by the scenario sources (private to the module).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "trainsim/scenario/param.hpp"

namespace trainsim::scenario::detail {

/// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions).
std::size_t editDistance(std::string_view a, std::string_view b);

/// The candidate closest to `word` if it is close enough to be a likely typo, else "".
std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates);

/// A JSON value as it should appear in a message: strings quoted, long values cut.
std::string describeValue(const Json& value);

/// Shortest round-tripping text of a number for docs and messages (1e-06 -> 1e-06, 0.5 -> 0.5).
std::string formatNumber(double value);

}  // namespace trainsim::scenario::detail
