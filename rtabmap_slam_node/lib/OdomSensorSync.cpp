#include "rtabmap_slam_node/OdomSensorSync.h"

#include "rtabmap_conversions/TfLookup.h"

namespace rtabmap_slam_node {

rtabmap::Transform odomSyncedLocalTransform(const tf2::BufferCore& buffer, const std::string& odomFrame,
                                            const std::string& baseFrame, const rtabmap::Transform& local,
                                            const ros::Time& odomStamp, const ros::Time& sensorStamp,
                                            double waitSeconds, std::string* error) {
  if (local.isNull() || odomStamp == sensorStamp) return local;
  const rtabmap::Transform motion =
      rtabmap_conversions::lookupMotion(buffer, odomFrame, baseFrame, odomStamp, sensorStamp, waitSeconds, error);
  if (motion.isNull()) return rtabmap::Transform();
  return motion * local;
}

}  // namespace rtabmap_slam_node
