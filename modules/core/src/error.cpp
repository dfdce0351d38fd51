#include "trainsim/core/error.hpp"

#include <cstring>

namespace trainsim {

int exitCodeFor(const std::exception& error) noexcept {
  return dynamic_cast<const ConfigError*>(&error) != nullptr ? kExitInvalidInput : kExitRuntime;
}

std::string systemErrorMessage(const std::string& what, const std::string& path, int errno_value) {
  // Built with append() rather than operator+ chains, which trip GCC 12's -Wrestrict
  // false positive (GCC bug 105329).
  std::string text = what;
  text.append(" ").append(path).append(": ").append(std::strerror(errno_value));
  return text;
}

}  // namespace trainsim
