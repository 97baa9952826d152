#include "rtabmap_conversions/TfLookup.h"

#include <geometry_msgs/TransformStamped.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <thread>

#include "rtabmap_conversions/TransformConversions.h"

namespace rtabmap_conversions {

namespace {

std::string formatStamp(const ros::Time& stamp) {
  if (stamp.isZero()) return "latest";
  char text[64];
  std::snprintf(text, sizeof(text), "t=%.6f s", stamp.toSec());
  return text;
}

// Frames tf has never heard of are the most common mistake (a typo, a driver not started):
// say so plainly instead of tf's generic extrapolation / connectivity text.
std::string missingFrames(const tf2::BufferCore& buffer, std::initializer_list<std::string> frames) {
  std::string out;
  for (const std::string& f : frames) {
    if (f.empty()) {
      out += (out.empty() ? "" : "; ") + std::string("a frame id is empty");
    } else if (!buffer._frameExists(f)) {
      out += (out.empty() ? "" : "; ") + ("frame '" + f + "' is unknown to tf");
    }
  }
  return out;
}

// Polls `ready` until it holds or waitSeconds have passed (wall clock); then runs `get`.
// Any exception from tf (or elsewhere) becomes a null result and a message.
rtabmap::Transform pollAndGet(const std::function<bool(std::string*)>& ready,
                              const std::function<geometry_msgs::TransformStamped()>& get, double waitSeconds,
                              const std::string& what, const std::function<std::string()>& missing,
                              std::string* error) {
  std::string tfError;
  try {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration<double>(waitSeconds > 0.0 ? waitSeconds : 0.0);
    bool available = ready(&tfError);
    while (!available && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      tfError.clear();
      available = ready(&tfError);
    }
    if (available) {
      const rtabmap::Transform t = transformFromMsg(get().transform);
      if (!t.isNull()) return t;
      tfError = "tf returned an invalid (NaN or zero-quaternion) transform";
    }
  } catch (const std::exception& e) {
    tfError = e.what();
  }
  if (error) {
    char wait[64];
    std::snprintf(wait, sizeof(wait), "%.3f s", waitSeconds > 0.0 ? waitSeconds : 0.0);
    const std::string why = missing();
    *error = what + " within " + wait + " (wait_for_transform_duration): " + (why.empty() ? tfError : why) +
             (why.empty() || tfError.empty() ? "" : " (tf: " + tfError + ")");
  }
  return rtabmap::Transform();
}

}  // namespace

rtabmap::Transform lookupTransform(const tf2::BufferCore& buffer, const std::string& targetFrame,
                                   const std::string& sourceFrame, const ros::Time& stamp, double waitSeconds,
                                   std::string* error) {
  if (!targetFrame.empty() && targetFrame == sourceFrame) return rtabmap::Transform::Identity();
  const std::string what =
      "cannot get the transform " + targetFrame + " <- " + sourceFrame + " at " + formatStamp(stamp);
  return pollAndGet(
      [&](std::string* e) { return buffer.canTransform(targetFrame, sourceFrame, stamp, e); },
      [&] { return buffer.lookupTransform(targetFrame, sourceFrame, stamp); }, waitSeconds, what,
      [&] { return missingFrames(buffer, {targetFrame, sourceFrame}); }, error);
}

rtabmap::Transform lookupMotion(const tf2::BufferCore& buffer, const std::string& fixedFrame,
                                const std::string& frame, const ros::Time& from, const ros::Time& to,
                                double waitSeconds, std::string* error) {
  const std::string what = "cannot get the motion of " + frame + " in " + fixedFrame + " from " +
                           formatStamp(from) + " to " + formatStamp(to);
  // tf's time travel: the pose of `frame` at `to` seen from `frame` at `from`.
  return pollAndGet(
      [&](std::string* e) { return buffer.canTransform(frame, from, frame, to, fixedFrame, e); },
      [&] { return buffer.lookupTransform(frame, from, frame, to, fixedFrame); }, waitSeconds, what,
      [&] { return missingFrames(buffer, {fixedFrame, frame}); }, error);
}

}  // namespace rtabmap_conversions
