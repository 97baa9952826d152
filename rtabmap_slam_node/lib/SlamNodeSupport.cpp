#include "rtabmap_slam_node/SlamNodeSupport.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace rtabmap_slam_node {

nav_msgs::OccupancyGrid gridMapToMsg(const rtabmap::GridMap& grid, const std_msgs::Header& header) {
  nav_msgs::OccupancyGrid msg;
  msg.header = header;
  msg.info.map_load_time = header.stamp;
  msg.info.resolution = grid.resolution;
  msg.info.width = grid.empty() ? 0 : grid.width();
  msg.info.height = grid.empty() ? 0 : grid.height();
  msg.info.origin.position.x = grid.originX;
  msg.info.origin.position.y = grid.originY;
  msg.info.origin.orientation.w = 1.0;
  if (grid.empty()) return msg;
  msg.data.resize(static_cast<size_t>(grid.width()) * grid.height());
  for (int row = 0; row < grid.height(); ++row) {
    // Row by row: the cv::Mat may be a view with a stride.
    std::memcpy(&msg.data[static_cast<size_t>(row) * grid.width()], grid.data.ptr<int8_t>(row), grid.width());
  }
  return msg;
}

Covariance6 motionCovariance(const Covariance6& current, const Covariance6* previous, bool cumulative,
                             double minVariance) {
  Covariance6 out = (cumulative && previous) ? Covariance6(current - *previous) : current;
  for (int i = 0; i < 6; ++i) {
    if (current(i, i) >= kUnobservedVariance) {
      // Unobserved axis: its variance is a convention, not integrated, and it is uncorrelated.
      out.row(i).setZero();
      out.col(i).setZero();
      out(i, i) = current(i, i);
    } else if (!(out(i, i) >= minVariance)) {
      // Also catches a covariance that shrank (odometry reset, or not cumulative after all).
      out.row(i).setZero();
      out.col(i).setZero();
      out(i, i) = minVariance;
    }
  }
  return out;
}

Covariance6 tfOdometryCovariance(double linearVariance, double angularVariance) {
  Covariance6 c = Covariance6::Zero();
  c.diagonal() << linearVariance, linearVariance, linearVariance, angularVariance, angularVariance, angularVariance;
  return c;
}

NodeArguments parseNodeArguments(const std::vector<std::string>& argv) {
  NodeArguments out;
  for (const std::string& a : argv) {
    if (a == "-d" || a == "--delete_db_on_start") {
      out.deleteDbOnStart = true;
    } else if (!a.empty()) {
      out.unknown.push_back(a);
    }
  }
  return out;
}

std::string expandHome(const std::string& path) {
  if (path != "~" && path.rfind("~/", 0) != 0) return path;
  const char* home = std::getenv("HOME");
  if (!home || !*home) return path;
  return std::string(home) + path.substr(1);
}

std::optional<ros::Time> MapToOdomStamps::next(const ros::Time& wanted, bool correctionChanged) {
  if (wanted != lastWanted_) {  // the clock moved (either way: listeners reset on a jump back)
    lastWanted_ = lastSent_ = wanted;
    return wanted;
  }
  if (!correctionChanged) return std::nullopt;
  lastSent_ += ros::Duration(0, 1);
  return lastSent_;
}

}  // namespace rtabmap_slam_node
