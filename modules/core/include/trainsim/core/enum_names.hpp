#pragma once

// Enums that appear in files (scenario JSON, railroad.json, CSVs) carry their names in one
// table beside the enum, found by argument-dependent lookup:
//
//   enum class TransitionShape { kClothoid, kBloss };
//   constexpr EnumName<TransitionShape> kTransitionShapeNames[] = {
//       {TransitionShape::kClothoid, "clothoid"}, {TransitionShape::kBloss, "bloss"}};
//   constexpr std::span<const EnumName<TransitionShape>> enumNames(TransitionShape) {
//     return kTransitionShapeNames;
//   }
//
// nameOf(value) and enumFromName<E>(name) then work for every such enum, and the scenario
// binding derives the JSON choices from the same table.

#include <optional>
#include <span>
#include <string_view>

namespace trainsim {

template <typename E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of `value` in its enum's table ("" if the table misses it, a programming error the
/// enum tests catch).
template <typename E>
constexpr std::string_view nameOf(E value) {
  for (const EnumName<E>& n : enumNames(E{}))
    if (n.value == value)
      return n.name;
  return {};
}

/// The value named `name`, or nullopt.
template <typename E>
constexpr std::optional<E> enumFromName(std::string_view name) {
  for (const EnumName<E>& n : enumNames(E{}))
    if (n.name == name)
      return n.value;
  return std::nullopt;
}

}  // namespace trainsim
