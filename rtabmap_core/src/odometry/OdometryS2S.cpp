// Scan-to-scan lidar odometry (see OdometryS2S.h).
#include "rtabmap_core/odometry/OdometryS2S.h"

#include "ScanOdometryCommon.h"

namespace rtabmap {

struct OdometryS2S::Impl {
  explicit Impl(const ParametersMap& p)
      : icp(scanodom::icpOptions(p)), keyFrameThr(Parameters::getDouble(p, Parameters::kOdomScanKeyFrameThr())) {}

  void setKeyFrame(const icp::IcpCloud& scan, const Transform& pose) {
    keyFrame = scan;
    keyFrame.buildIndex(icp.maxCorrespondenceDistance);
    keyFramePose = pose;
    ++keyFrames;
  }

  IcpOptions icp;
  double keyFrameThr;
  icp::IcpCloud keyFrame;  // in its own base frame
  Transform keyFramePose;  // odometry frame
  int keyFrames = 0;
  scanodom::LostMotion lostMotion;
};

OdometryS2S::OdometryS2S(const ParametersMap& parameters)
    : Odometry(parameters), impl_(std::make_unique<Impl>(parameters)) {}

OdometryS2S::~OdometryS2S() = default;

LaserScan OdometryS2S::keyFrameScan() const {
  return icp::toLaserScan(*impl_->keyFrame.cloud, impl_->keyFrame.is2d, impl_->keyFrame.hasNormals);
}

Transform OdometryS2S::keyFramePose() const { return impl_->keyFramePose; }

int OdometryS2S::keyFrames() const { return impl_->keyFrames; }

bool OdometryS2S::needsInitialisation() const { return impl_->keyFrame.empty(); }

void OdometryS2S::resetMap(const Transform&) {
  impl_->keyFrame = icp::IcpCloud();
  impl_->keyFramePose = Transform();
  impl_->keyFrames = 0;
  impl_->lostMotion.reset();
}

Transform OdometryS2S::computeTransform(SensorData& data, const Transform& guess, OdometryInfo* info) {
  Impl& s = *impl_;
  const Transform& lostMotion = s.lostMotion.beginAttempt(framesProcessed(), guess);
  icp::IcpCloud scan;
  std::string why;
  if (!scanodom::prepareFrameScan(data, s.icp, &scan, &why)) {
    info->lostReason = why;
    return Transform();
  }
  const Transform& previous = getPose();
  if (s.keyFrame.empty()) {
    s.setKeyFrame(scan, previous);
    info->keyFrameAdded = true;
    info->localKeyFrames = 1;
    info->localScanMapSize = s.keyFrame.size();
    info->reg.success = true;
    s.lostMotion.succeeded();
    return Transform::Identity();
  }
  if (scan.is2d != s.keyFrame.is2d) {
    info->lostReason = std::string("the scan is ") + (scan.is2d ? "2D" : "3D") + " but the key frame is " +
                       (s.keyFrame.is2d ? "2D" : "3D") + " (reset odometry to change sensors)";
    return Transform();
  }

  // Registration in the key frame's base frame.
  const Transform poseGuess = previous * lostMotion * (guess.isNull() ? Transform::Identity() : guess);
  const Transform relative =
      scanodom::registerScan(s.keyFrame, scan, s.keyFramePose.inverse() * poseGuess, guess.isNull(), s.icp,
                              &info->reg);
  info->localKeyFrames = 1;
  info->localScanMapSize = s.keyFrame.size();
  if (relative.isNull()) {
    info->lostReason = "scan-to-scan ICP: " + info->reg.rejectedMsg;
    return Transform();
  }
  s.lostMotion.succeeded();
  const Transform pose = s.keyFramePose * relative;
  if (scanodom::belowKeyFrameThreshold(info->reg.icpInliersRatio, s.keyFrameThr)) {
    s.setKeyFrame(scan, pose);
    info->keyFrameAdded = true;
    info->localScanMapSize = s.keyFrame.size();
  }
  return previous.inverse() * pose;
}

}  // namespace rtabmap
