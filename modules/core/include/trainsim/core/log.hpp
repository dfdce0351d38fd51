#pragma once

#include <string_view>

namespace trainsim {

enum class LogLevel { kDebug, kInfo, kWarn, kError, kOff };

/// Parses "debug", "info", "warn", "error", "off"; throws ConfigError naming `what` otherwise.
LogLevel parseLogLevel(std::string_view text, std::string_view what);

/// Sends log lines to standard error ("[level] message") at `level` and above. Call once from
/// an application's main; before that, info and above are logged.
void setLogLevel(LogLevel level);

void logDebug(std::string_view message);
void logInfo(std::string_view message);
void logWarn(std::string_view message);
void logError(std::string_view message);

}  // namespace trainsim
