#include "rtabmap_core/common/Log.h"

#include <atomic>
#include <iostream>
#include <mutex>

namespace rtabmap {

namespace {

std::mutex& sinkMutex() {
  static std::mutex m;
  return m;
}

LogSink& sinkRef() {
  static LogSink sink = [](LogLevel level, const std::string& message) {
    if (level >= LogLevel::kWarning) {
      std::cerr << "[" << logLevelName(level) << "] " << message << std::endl;
    }
  };
  return sink;
}

std::atomic<int>& levelRef() {
  static std::atomic<int> level{static_cast<int>(LogLevel::kInfo)};
  return level;
}

}  // namespace

void setLogSink(LogSink sink) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  sinkRef() = std::move(sink);
}

void setLogLevel(LogLevel level) { levelRef() = static_cast<int>(level); }

LogLevel logLevel() { return static_cast<LogLevel>(levelRef().load()); }

void logMessage(LogLevel level, const std::string& message) {
  std::lock_guard<std::mutex> lock(sinkMutex());
  if (sinkRef()) sinkRef()(level, message);
}

const char* logLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "DEBUG";
    case LogLevel::kInfo: return "INFO";
    case LogLevel::kWarning: return "WARN";
    case LogLevel::kError: return "ERROR";
  }
  return "?";
}

}  // namespace rtabmap
