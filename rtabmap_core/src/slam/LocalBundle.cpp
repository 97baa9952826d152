#include "LocalBundle.h"

#include <opencv2/core.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "LinkRegistration.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap {
namespace {

bool finite3(const cv::Point3f& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

cv::Point3f transformPoint(const Transform& t, const cv::Point3f& p) {
  const Eigen::Vector3d q = t.toEigen() * Eigen::Vector3d(p.x, p.y, p.z);
  return cv::Point3f(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
}

// Depth along the optical axis of a base-frame point, 0 when unknown or behind the camera.
float depthInCamera(const cv::Point3f& p, const Transform& local) {
  if (!finite3(p)) return 0.0f;
  const cv::Point3f c = transformPoint(local.inverse(), p);
  return c.z > 0.0f ? c.z : 0.0f;
}

// The single (left) camera of a node and its stereo baseline; false with several cameras or none.
bool singleCameraOf(const SensorData& data, CameraModel* model, double* baseline) {
  if (data.isStereo()) {
    if (data.stereoCameraModels().size() != 1) return false;
    *model = data.stereoCameraModels().front().left();
    *baseline = data.stereoCameraModels().front().baseline();
  } else {
    if (data.cameraModels().size() != 1) return false;
    *model = data.cameraModels().front();
    *baseline = 0.0;
  }
  return model->isValidForProjection();
}

// Adds `node`'s words seen once, with 3D and a descriptor, placed by `pose` (node -> center).
// Words already in the map keep their point. The center's observations are kept.
void addNodeWords(const Signature& node, const Transform& pose, LocalFeatureMap& map, std::set<int>& inMap) {
  BundleAdjustmentFrame view;
  if (!singleCameraOf(node.sensorData(), &view.model, &view.baseline)) return;
  view.pose = pose;
  const std::multimap<int, int>& words = node.getWords();
  const cv::Mat& descriptors = node.getWordsDescriptors();
  int observed = 0;
  for (const auto& [wordId, index] : words) {
    if (words.count(wordId) != 1) continue;  // an ambiguous word: which keypoint is the point?
    const size_t i = static_cast<size_t>(index);
    if (i >= node.getWords3().size() || i >= node.getWordsKpts().size() || index >= descriptors.rows) continue;
    const cv::Point3f& p = node.getWords3()[i];
    if (!finite3(p)) continue;
    if (inMap.insert(wordId).second) {
      map.frame.points3D.push_back(transformPoint(pose, p));
      map.frame.descriptors.push_back(descriptors.row(index));
      map.frame.ids.push_back(wordId);
    }
    if (node.id() == map.center) {
      map.observations.push_back(
          {node.id(), wordId, node.getWordsKpts()[i].pt, depthInCamera(p, view.model.localTransform())});
    }
    ++observed;
  }
  if (observed > 0) map.views[node.id()] = view;
}

// Covariance of the inverse of a transform whose covariance is `covariance` (right perturbations,
// as the links carry them): Link::inverse moves the information through the adjoint.
Eigen::Matrix<double, 6, 6> inverseCovariance(const Transform& t, const Eigen::Matrix<double, 6, 6>& covariance) {
  const Link forward(0, 1, Link::kGlobalClosure, t, informationOf(covariance, false));
  return forward.inverse().infMatrix().inverse();
}

}  // namespace

LocalFeatureMap localFeatureMap(const memory::Memory& memory, int center) {
  LocalFeatureMap map;
  map.center = center;
  const Signature* node = memory.signature(center);
  if (!node) {
    map.problem = "node " + std::to_string(center) + " is not in memory";
    return map;
  }
  if (node->getWordsDescriptors().empty()) {
    map.problem = "node " + std::to_string(center) + " has no word descriptors (Mem/RawDescriptorsKept false)";
    return map;
  }
  std::set<int> inMap;
  addNodeWords(*node, Transform::Identity(), map, inMap);
  if (!map.views.count(center)) {
    map.problem = "node " + std::to_string(center) + " has no single camera or no words with 3D";
    return map;
  }
  for (const auto& [to, link] : node->getLinks()) {
    if (link.type() != Link::kNeighbor || to == center || link.transform().isNull()) continue;
    const Signature* neighbor = memory.signature(to);
    if (!neighbor || neighbor->getWordsDescriptors().empty()) continue;
    if (neighbor->getWordsDescriptors().type() != node->getWordsDescriptors().type() ||
        neighbor->getWordsDescriptors().cols != node->getWordsDescriptors().cols) {
      continue;  // words of another detector (a session with other Kp/ parameters)
    }
    addNodeWords(*neighbor, link.transform(), map, inMap);
  }
  if (map.views.size() < 2) map.problem = "node " + std::to_string(center) + " has no neighbour with words in memory";
  return map;
}

Transform registerToLocalMap(const LocalFeatureMap& map, Signature& current, const RegistrationVis& visual,
                             bool repeatOnce, const Transform& guess, RegistrationInfo* infoOut) {
  RegistrationInfo scratch;
  RegistrationInfo& info = infoOut ? *infoOut : scratch;
  info = RegistrationInfo();
  auto reject = [&](const std::string& why) {
    info.success = false;
    info.rejectedMsg = why;
    return Transform();
  };
  if (!map.problem.empty()) return reject("local feature map: " + map.problem);
  if (map.views.count(current.id())) return reject("node " + std::to_string(current.id()) + " is in the local map");
  std::string problem;
  const VisualFrame frame = visual.frameOf(current, false, &problem);
  if (!problem.empty()) return reject("node " + std::to_string(current.id()) + ": " + problem);
  if (frame.severalCameras() || !frame.model.isValidForProjection()) {
    return reject("node " + std::to_string(current.id()) + " has no single camera");
  }

  // The map's registration gives the pose of the current node in the center's frame.
  VisualCorrespondences details;
  Transform pose;
  try {
    pose = visual.computeTransform(map.frame, frame, guess.isNull() ? Transform() : guess.inverse(), &info, &details);
    if (!pose.isNull() && repeatOnce && guess.isNull()) {
      // Reg/RepeatOnce, as for two nodes: matched again where the first estimate projects the map.
      RegistrationInfo again;
      VisualCorrespondences againDetails;
      const Transform second = visual.computeTransform(map.frame, frame, pose, &again, &againDetails);
      if (second.isNull()) {
        return reject("registered again from its own first estimate (Reg/RepeatOnce): " + again.rejectedMsg);
      }
      pose = second;
      info = std::move(again);
      details = std::move(againDetails);
    }
  } catch (const cv::Exception& e) {
    return reject(std::string("OpenCV error during visual registration: ") + e.what());
  } catch (const std::invalid_argument& e) {
    return reject(e.what());
  }
  if (pose.isNull()) return info.rejectedMsg.empty() ? reject("no transform") : Transform();

  struct Seen {
    cv::Point3f point;  // the map's, in the center's frame
    cv::Point2f uv;     // in the current image
    float depth;        // in the current camera, 0 = unknown
  };
  std::map<int, Seen> inlierWords;
  for (int k : details.inliers) {
    const cv::DMatch& m = details.matches[static_cast<size_t>(k)];
    const cv::Point3f p = static_cast<size_t>(m.trainIdx) < frame.points3D.size()
                              ? frame.points3D[static_cast<size_t>(m.trainIdx)]
                              : cv::Point3f(NAN, NAN, NAN);
    inlierWords[map.frame.ids[static_cast<size_t>(m.queryIdx)]] = {
        map.frame.points3D[static_cast<size_t>(m.queryIdx)], details.toPoints[static_cast<size_t>(k)],
        depthInCamera(p, frame.model.localTransform())};
  }

  // Bundle adjustment of the new pose against the center's own view of the inliers. The
  // neighbours served the matching; they stay out of the refinement because their words meet the
  // center's through word ids (the vocabulary's quantisation aliases look-alike corners) and
  // their poses through links with their own errors: on the simulator's loop, 8.3 mm mean
  // loop-closure error with them fixed at their links, 6.9 free, 6.7 without them, against 6.9
  // from the two nodes alone.
  std::map<int, BundleAdjustmentFrame> frames;
  frames[map.center] = map.views.at(map.center);
  frames[map.center].fixed = true;
  frames[current.id()] = {pose, frame.model, false, frame.stereoBaseline};
  std::map<int, cv::Point3f> points;
  std::vector<BundleAdjustmentObservation> observations;
  for (const BundleAdjustmentObservation& o : map.observations) {
    if (inlierWords.count(o.point)) {
      points[o.point] = inlierWords.at(o.point).point;
      observations.push_back(o);
    }
  }
  for (const auto& [wordId, seen] : inlierWords) {
    if (points.count(wordId)) observations.push_back({current.id(), wordId, seen.uv, seen.depth});
  }
  BundleAdjustmentOptions options;
  options.huberPixels = visual.options().pnp.reprojError;
  const BundleAdjustmentSummary summary = bundleAdjust(frames, points, observations, options);
  if (summary.success) {
    std::set<int> outliers;  // words the adjusted current view sees far from their point
    for (size_t o : summary.outliers) {
      if (observations[o].frame == current.id()) outliers.insert(observations[o].point);
    }
    if (!outliers.empty()) {
      std::vector<int> kept;
      for (int id : info.inliersIDs) {
        if (!outliers.count(id)) kept.push_back(id);
      }
      info.inliersIDs = kept;
      info.inliers = static_cast<int>(kept.size());
    }
    if (info.inliers < visual.options().minInliers) {
      std::ostringstream s;
      s << "only " << info.inliers << " inliers left after the local bundle adjustment, Vis/MinInliers is "
        << visual.options().minInliers;
      return reject(s.str());
    }
    pose = frames[current.id()].pose;
    if (visual.options().force3DoF) pose = pose.to3DoF();
  }
  info.covariance = inverseCovariance(pose, info.covariance);
  info.success = true;
  return pose.inverse();
}

}  // namespace rtabmap
