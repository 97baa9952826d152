#pragma once
// Logging for the core library. The core never prints on its own terms: it hands each message
// to a sink, which the tools point at stderr and the ROS layer at rosconsole.
#include <functional>
#include <sstream>
#include <string>

namespace rtabmap {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

using LogSink = std::function<void(LogLevel, const std::string& message)>;

// Replaces the sink (thread-safe). The default sink writes warnings and errors to stderr.
void setLogSink(LogSink sink);
// Messages below this level are dropped before formatting reaches the sink.
void setLogLevel(LogLevel level);
LogLevel logLevel();
// Sends one message to the sink (thread-safe).
void logMessage(LogLevel level, const std::string& message);
const char* logLevelName(LogLevel level);

}  // namespace rtabmap

// Stream-style macros: RTABMAP_WARN("node " << id << " has no words");
#define RTABMAP_LOG_AT(level, expr)                                 \
  do {                                                              \
    if (static_cast<int>(level) >= static_cast<int>(::rtabmap::logLevel())) { \
      std::ostringstream rtabmap_log_stream_;                       \
      rtabmap_log_stream_ << expr;                                  \
      ::rtabmap::logMessage(level, rtabmap_log_stream_.str());      \
    }                                                               \
  } while (0)
#define RTABMAP_DEBUG(expr) RTABMAP_LOG_AT(::rtabmap::LogLevel::kDebug, expr)
#define RTABMAP_INFO(expr) RTABMAP_LOG_AT(::rtabmap::LogLevel::kInfo, expr)
#define RTABMAP_WARN(expr) RTABMAP_LOG_AT(::rtabmap::LogLevel::kWarning, expr)
#define RTABMAP_ERROR(expr) RTABMAP_LOG_AT(::rtabmap::LogLevel::kError, expr)
