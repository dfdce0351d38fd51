#include "trainsim/io/kitti_calib.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "trainsim/core/error.hpp"

namespace trainsim::io {

KittiCalib parseKittiCalib(std::string_view text, const std::string& path) {
  KittiCalib out;
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r')
      line.remove_suffix(1);
    if (line.find_first_not_of(" \t") == std::string_view::npos)
      continue;
    const std::size_t colon = line.find(':');
    const auto bad = [&](std::string_view why) {
      return IoError(fmt::format("{}:{}: {}", path, line_number, why));
    };
    if (colon == std::string_view::npos || colon == 0)
      throw bad("not 'NAME: numbers'");
    std::string name(line.substr(0, colon));
    std::vector<double> numbers;
    std::string_view rest = line.substr(colon + 1);
    while (true) {
      const std::size_t first = rest.find_first_not_of(" \t");
      if (first == std::string_view::npos)
        break;
      rest.remove_prefix(first);
      double value = 0.0;
      const auto [next, error] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
      const std::size_t used = static_cast<std::size_t>(next - rest.data());
      if (error != std::errc{} || !std::isfinite(value) ||
          (used < rest.size() && rest[used] != ' ' && rest[used] != '\t'))
        throw bad(
            fmt::format("{}: '{}' is not a finite number", name,
                        rest.substr(0, std::min<std::size_t>(rest.find_first_of(" \t"), 32))));
      numbers.push_back(value);
      rest.remove_prefix(used);
    }
    if (!out.emplace(name, std::move(numbers)).second)
      throw bad(fmt::format("{} is given twice", name));
  }
  return out;
}

}  // namespace trainsim::io
