#include "rtabmap_conversions/CoreLog.h"

#include <gtest/gtest.h>
#include <ros/console.h>

#include <string>
#include <vector>

#include "rtabmap_core/common/Log.h"

namespace {

struct Logged {
  ros::console::Level level;
  std::string text;
};

// Sees what rosconsole prints (what goes to /rosout and the log files in a node).
class RecordingAppender : public ros::console::LogAppender {
 public:
  void log(ros::console::Level level, const char* str, const char*, const char*, int) override {
    logged.push_back({level, str});
  }
  std::vector<Logged> logged;
};

bool contains(const std::vector<Logged>& logged, ros::console::Level level, const std::string& text) {
  for (const Logged& l : logged) {
    if (l.level == level && l.text.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST(CoreLog, CoreMessagesReachRosconsoleWithTheirLevel) {
  RecordingAppender appender;
  ros::console::register_appender(&appender);
  rtabmap_conversions::routeCoreLogToRosconsole();
  rtabmap_conversions::routeCoreLogToRosconsole();  // a second nodelet: still one route
  RTABMAP_INFO("core info " << 1);
  RTABMAP_WARN("core warning " << 2);
  RTABMAP_ERROR("core error " << 3);
  ros::console::deregister_appender(&appender);
  EXPECT_TRUE(contains(appender.logged, ros::console::levels::Info, "core info 1"));
  EXPECT_TRUE(contains(appender.logged, ros::console::levels::Warn, "core warning 2"));
  EXPECT_TRUE(contains(appender.logged, ros::console::levels::Error, "core error 3"));
  int warnings = 0;
  for (const Logged& l : appender.logged) warnings += l.text.find("core warning 2") != std::string::npos;
  EXPECT_EQ(warnings, 1) << "each message once, whatever the number of nodelets";
}
