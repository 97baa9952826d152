// Scan-to-map lidar odometry (see OdometryS2M.h).
#include "rtabmap_core/odometry/OdometryS2M.h"

#include "ScanMap.h"
#include "ScanOdometryCommon.h"

namespace rtabmap {

struct OdometryS2M::Impl {
  explicit Impl(const ParametersMap& p)
      : icp(scanodom::icpOptions(p)),
        map(scanodom::ScanMapOptions::fromParameters(p)),
        keyFrameThr(Parameters::getDouble(p, Parameters::kOdomScanKeyFrameThr())),
        keyFrameLinear(Parameters::getFloat(p, Parameters::kOdomF2MScanKeyFrameLinear())),
        keyFrameAngular(Parameters::getFloat(p, Parameters::kOdomF2MScanKeyFrameAngular())) {}

  // Key frame on poor overlap with the map (the scan sees new surfaces) or on motion.
  bool isKeyFrame(double ratio, const Transform& pose) const {
    if (scanodom::belowKeyFrameThreshold(ratio, keyFrameThr)) return true;
    const Transform moved = lastKeyFramePose.inverse() * pose;
    return (keyFrameLinear > 0.0f && moved.getNorm() > keyFrameLinear) ||
           (keyFrameAngular > 0.0f && moved.getAngle() > keyFrameAngular);
  }

  IcpOptions icp;
  scanodom::ScanMap map;
  double keyFrameThr;
  float keyFrameLinear;
  float keyFrameAngular;
  Transform lastKeyFramePose;
  int keyFramesAdded = 0;
  scanodom::LostMotion lostMotion;
};

OdometryS2M::OdometryS2M(const ParametersMap& parameters)
    : Odometry(parameters), impl_(std::make_unique<Impl>(parameters)) {}

OdometryS2M::~OdometryS2M() = default;

LaserScan OdometryS2M::localMap() const {
  const auto& cloud = impl_->map.cloud();
  return icp::toLaserScan(*cloud.cloud, cloud.is2d, cloud.hasNormals);
}

int OdometryS2M::keyFrames() const { return impl_->keyFramesAdded; }

bool OdometryS2M::needsInitialisation() const { return impl_->map.empty(); }

void OdometryS2M::resetMap(const Transform&) {
  impl_->map.clear();
  impl_->lastKeyFramePose = Transform();
  impl_->keyFramesAdded = 0;
  impl_->lostMotion.reset();
}

Transform OdometryS2M::computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) {
  Impl& m = *impl_;
  const Transform& lostMotion = m.lostMotion.beginAttempt(framesProcessed(), guess);
  icp::IcpCloud scan;
  std::string why;
  if (!scanodom::prepareFrameScan(data, m.icp, &scan, &why)) {
    info->lostReason = why;
    return Transform();
  }
  const Transform& previous = getPose();

  if (m.map.empty()) {
    // The first scan is the map, at the initial pose.
    m.map.addKeyFrame(scan, previous);
    m.lastKeyFramePose = previous;
    m.keyFramesAdded = 1;
    info->keyFrameAdded = true;
    info->localScanMapSize = m.map.size();
    info->localKeyFrames = m.map.keyFrames();
    info->reg.success = true;
    m.lostMotion.succeeded();
    return Transform::Identity();
  }
  if (scan.is2d != m.map.is2d()) {
    info->lostReason = std::string("the scan is ") + (scan.is2d ? "2D" : "3D") + " but the scan map is " +
                       (m.map.is2d() ? "2D" : "3D") + " (reset odometry to change sensors)";
    return Transform();
  }

  const Transform poseGuess = previous * lostMotion * (guess.isNull() ? Transform::Identity() : guess);
  const Transform pose = scanodom::registerScan(m.map.cloud(), scan, poseGuess, guess.isNull(), m.icp, &info->reg);
  info->localScanMapSize = m.map.size();
  info->localKeyFrames = m.map.keyFrames();
  if (pose.isNull()) {
    info->lostReason = "scan-to-map ICP: " + info->reg.rejectedMsg;
    return Transform();
  }
  m.lostMotion.succeeded();

  if (m.isKeyFrame(info->reg.icpInliersRatio, pose)) {
    m.map.addKeyFrame(scan, pose);
    m.lastKeyFramePose = pose;
    ++m.keyFramesAdded;
    info->keyFrameAdded = true;
    info->localScanMapSize = m.map.size();
    info->localKeyFrames = m.map.keyFrames();
  }
  return previous.inverse() * pose;
}

}  // namespace rtabmap
