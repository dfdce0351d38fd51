#include "trainsim/core/error.hpp"

#include <cstring>

namespace trainsim {

int exitCodeFor(const std::exception& error) noexcept {
  return dynamic_cast<const ConfigError*>(&error) != nullptr ? kExitInvalidInput : kExitRuntime;
}

std::string messageValue(std::string_view text, std::size_t max) {
  std::string out;
  for (const char c : text) {
    if (out.size() >= max) {
      out.resize(max > 3 ? max - 3 : 0);
      out += "...";
      break;
    }
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += "\\t";
    else if (static_cast<unsigned char>(c) < 0x20)
      out += "?";
    else
      out += c;
  }
  return out;
}

std::string systemErrorMessage(const std::string& what, const std::string& path, int errno_value) {
  // Built with append() rather than operator+ chains, which trip GCC 12's -Wrestrict
  // false positive (GCC bug 105329).
  std::string text = what;
  text.append(" ").append(path).append(": ").append(std::strerror(errno_value));
  return text;
}

}  // namespace trainsim
