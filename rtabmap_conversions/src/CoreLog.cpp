#include "rtabmap_conversions/CoreLog.h"

#include <ros/console.h>

#include <mutex>

#include "rtabmap_core/common/Log.h"

namespace rtabmap_conversions {

void routeCoreLogToRosconsole() {
  static std::once_flag once;
  std::call_once(once, [] {
    rtabmap::setLogSink([](rtabmap::LogLevel level, const std::string& message) {
      switch (level) {
        case rtabmap::LogLevel::kDebug: ROS_DEBUG_NAMED("core", "%s", message.c_str()); break;
        case rtabmap::LogLevel::kInfo: ROS_INFO_NAMED("core", "%s", message.c_str()); break;
        case rtabmap::LogLevel::kWarning: ROS_WARN_NAMED("core", "%s", message.c_str()); break;
        case rtabmap::LogLevel::kError: ROS_ERROR_NAMED("core", "%s", message.c_str()); break;
      }
    });
  });
}

}  // namespace rtabmap_conversions
