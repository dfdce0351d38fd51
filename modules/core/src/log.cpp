#include "trainsim/core/log.hpp"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <string>

#include "trainsim/core/error.hpp"

namespace trainsim {
namespace {

spdlog::logger& logger() {
  // stderr keeps standard output free for data (`trainsim defaults`, --progress json).
  static const std::shared_ptr<spdlog::logger> instance = [] {
    auto l = std::make_shared<spdlog::logger>("trainsim",
                                              std::make_shared<spdlog::sinks::stderr_sink_mt>());
    l->set_pattern("[%l] %v");
    l->set_level(spdlog::level::info);
    return l;
  }();
  return *instance;
}

}  // namespace

LogLevel parseLogLevel(std::string_view text, std::string_view what) {
  if (text == "debug")
    return LogLevel::kDebug;
  if (text == "info")
    return LogLevel::kInfo;
  if (text == "warn")
    return LogLevel::kWarn;
  if (text == "error")
    return LogLevel::kError;
  if (text == "off")
    return LogLevel::kOff;
  throw ConfigError(std::string(what) + ": '" + std::string(text) +
                    "' is not one of debug, info, warn, error, off");
}

void setLogLevel(LogLevel level) {
  static constexpr spdlog::level::level_enum kMap[] = {spdlog::level::debug, spdlog::level::info,
                                                       spdlog::level::warn, spdlog::level::err,
                                                       spdlog::level::off};
  logger().set_level(kMap[static_cast<int>(level)]);
}

void logDebug(std::string_view message) {
  logger().debug(message);
}
void logInfo(std::string_view message) {
  logger().info(message);
}
void logWarn(std::string_view message) {
  logger().warn(message);
}
void logError(std::string_view message) {
  logger().error(message);
}

}  // namespace trainsim
