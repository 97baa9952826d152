// What a new node is made of (Algorithm 2 with the metric parts of JFR 2019, 3.2): visual
// words, local occupancy grid, compressed sensor data, odometry pose and link information; and
// the registrations that give links their transforms.
#include <Eigen/LU>

#include <algorithm>
#include <future>
#include <optional>
#include <stdexcept>

#include "LocalBundle.h"
#include "OdometryPrior.h"
#include "ProximityByTime.h"
#include "RtabmapImpl.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/geometry/DepthFormat.h"
#include "rtabmap_core/geometry/ImageDecimation.h"
#include "rtabmap_core/maps/LocalGridMaker.h"

namespace rtabmap {

// The words' keypoints are in the image the node keeps, Mem/ImagePostDecimation times smaller
// than the input: visual registration pairs them with the kept camera models.
void Rtabmap::Impl::extractWords(const SensorData& data, memory::LocationInput& in) {
  if (!wordDetector) return;
  const float toKept = 1.f / static_cast<float>(options.imagePostDecimation);
  // Mem/UseOdomFeatures: odometry already extracted features of the same kind (full-size
  // keypoints); Memory keeps the Kp/MaxFeatures strongest of them.
  if (options.useOdomFeatures && odomFeaturesCompatible && !data.keypoints().empty() &&
      data.descriptors().rows == static_cast<int>(data.keypoints().size())) {
    in.keypoints = data.keypoints();
    scaleKeypoints(in.keypoints, toKept);
    in.descriptors = data.descriptors();
    if (data.keypoints3D().size() == data.keypoints().size()) in.points3D = data.keypoints3D();
    return;
  }
  if (data.imageRaw().empty()) return;
  FeatureExtractionInfo info;
  ImageFeatures f = wordDetector->extract(decimateImages(data, options.imagePreDecimation), &info);
  if (!info.problem.empty()) RTABMAP_DEBUG("no visual words for frame " << data.id() << ": " << info.problem);
  in.keypoints = std::move(f.keypoints);
  scaleKeypoints(in.keypoints, static_cast<float>(options.imagePreDecimation) * toKept);
  in.descriptors = f.descriptors;
  in.points3D = std::move(f.points3D);
}

memory::LocationInput Rtabmap::Impl::makeLocation(const SensorData& raw, const Transform& odom,
                                                  const Covariance6& covariance) {
  memory::LocationInput in;
  SensorData data = raw;
  if (data.imageRaw().empty() && !data.imageCompressed().empty()) {
    try {
      data.uncompress(true, true, false, false);
    } catch (const Error& e) {
      RTABMAP_WARN("frame " << raw.id() << ": images cannot be uncompressed (" << e.what() << "): no visual words");
    }
  }
  // Mem/CompressionParallelized: the images the node keeps are shrunk and compressed on other
  // threads while the markers, the words and the grid are made from the full images.
  std::future<SensorData> keptImages;
  if (options.compressionParallelized && options.binDataKept && !data.imageRaw().empty()) {
    keptImages = std::async(std::launch::async, [this, images = imagesOf(data)] { return imagesForMemory(images, true); });
  }
  detectMarkers(data);  // before decimation: the markers' corners need every pixel
  takeCarriedLandmarks(data, odom);
  {
    StageTimer t(stats, Statistics::kTimingMemKeypoints_detection);
    extractWords(data, in);
  }
  if (scanFilter.active() && !data.laserScanRaw().empty()) {
    // Before the local grid: the grid, the database and every registration get the filtered scan.
    StageTimer t(stats, "Timing/Mem_scan_filtering/ms");
    applyScanFilter(data, raw.id());
  }
  if (gridOptions && data.localGrid().isEmpty()) {
    StageTimer t(stats, Statistics::kTimingMemOccupancy_grid);
    LocalGridResult g = createLocalGrid(data, *gridOptions);
    if (g.success) {
      data.setLocalGrid(g.grid);
    } else {
      RTABMAP_DEBUG("frame " << raw.id() << ": no local grid: " << g.why);
    }
  }
  {
    // Working Memory holds images compressed (what the database stores); the scan stays raw
    // too, as proximity detection matches it again and again.
    StageTimer t(stats, Statistics::kTimingMemCompressing_data);
    if (keptImages.valid()) {
      keepImages(data, keptImages.get());
    } else {
      compressForMemory(data);  // after the local grid: it uses all pixels
    }
    data.setFeatures({}, {}, cv::Mat());  // the words hold what is kept of them
  }
  in.data = data;
  setFrameOf(in, raw, odom, covariance);
  return in;
}

void Rtabmap::Impl::applyScanFilter(SensorData& data, int frameId) const {
  std::string why;
  const LaserScan filtered = filterScan(data.laserScanRaw(), scanFilter, &why);
  if (filtered.empty()) {
    RTABMAP_WARN("frame " << frameId << ": the scan is kept unfiltered, the Mem/LaserScan* filters leave nothing of it: " << why);
  } else {
    data.setLaserScan(filtered);
  }
}

void Rtabmap::Impl::compressForMemory(SensorData& data) const {
  keepImages(data, imagesForMemory(imagesOf(data), false));
}

SensorData Rtabmap::Impl::imagesOf(const SensorData& data) {
  SensorData images;
  if (data.isStereo()) {
    images.setStereoImage(data.imageRaw(), data.depthOrRightRaw(), data.stereoCameraModels());
  } else {
    images.setRGBDImage(data.imageRaw(), data.depthOrRightRaw(), data.cameraModels());
  }
  return images;
}

// What Working Memory and the database keep of the images: Mem/ImagePostDecimation times
// smaller, the depth in millimetres with Mem/SaveDepth16Format, compressed. Mem/BinDataKept
// false: only the camera models, scaled as the words' keypoints were.
SensorData Rtabmap::Impl::imagesForMemory(SensorData images, bool parallel) const {
  images = decimateImages(images, options.imagePostDecimation);
  if (!options.binDataKept) {
    if (images.isStereo()) {
      images.setStereoImage(cv::Mat(), cv::Mat(), images.stereoCameraModels());
    } else {
      images.setRGBDImage(cv::Mat(), cv::Mat(), images.cameraModels());
    }
    return images;
  }
  if (options.saveDepth16 && !images.isStereo() && images.depthOrRightRaw().type() == CV_32FC1) {
    images.setRGBDImage(images.imageRaw(), depthToMillimetres(images.depthOrRightRaw()), images.cameraModels());
  }
  images.compressImages(options.imageFormat, parallel);
  return images;
}

// The node's data takes the kept images (the raw ones only with Mem/ImageKept); the scan stays
// raw, as proximity detection matches it again and again.
void Rtabmap::Impl::keepImages(SensorData& data, const SensorData& images) const {
  if (images.isStereo()) {
    data.setStereoImage(images.imageRaw(), images.depthOrRightRaw(), images.stereoCameraModels());
  } else {
    data.setRGBDImage(images.imageRaw(), images.depthOrRightRaw(), images.cameraModels());
  }
  data.compressScanAndUserData();
  data.setCompressed(images.imageCompressed(), images.depthOrRightCompressed(), data.laserScanCompressed(),
                     data.userDataCompressed());
  if (!options.imageKept) {
    const LaserScan scan = data.laserScanRaw();
    data.clearRaw();
    data.setLaserScan(scan);
  }
}

void Rtabmap::Impl::setFrameOf(memory::LocationInput& in, const SensorData& raw, const Transform& odom,
                               const Covariance6& covariance) const {
  if (!options.generateIds && options.incremental) in.id = raw.id();  // checked by checkInput
  in.pose = odom;
  in.stamp = raw.stamp();
  in.mapId = mapId;
  in.odomInformation = informationOf(covariance, options.covOffDiagIgnored);
}

// The weight of a refined neighbour link: the registration's own covariance, the model that
// also weighs the proximity and loop-closure links it competes with in the graph. Keeping the
// wheel odometry's (a model of the guess ICP replaced, isotropic, and orders of magnitude
// stiffer than ICP's for the same scans) made every loop-closing proximity link negligible: the
// optimiser bent the chain of neighbour links least and left the loops open. A registration
// without a covariance keeps the odometry's.
namespace {
Link::InfMatrix refinedInformation(const RegistrationInfo& info, const Link& odometry, bool diagonalOnly) {
  const bool measured = info.covariance.allFinite() && info.covariance.diagonal().minCoeff() > 0.0;
  return measured ? informationOf(info.covariance, diagonalOnly) : odometry.infMatrix();
}
}  // namespace

// Mem/IntermediateNodeDataKept false: the pose is the node (the data's stamp, ground truth and
// IMU stay: the trajectory's evaluation and the gravity link use them). True: the data as a
// node keeps it, compressed, without what only detection uses (words, grid, markers).
memory::LocationInput Rtabmap::Impl::makeIntermediateLocation(const SensorData& raw, const Transform& odom,
                                                              const Covariance6& covariance) {
  memory::LocationInput in;
  in.intermediate = true;
  if (options.intermediateNodeDataKept) {
    SensorData data = raw;
    if (scanFilter.active() && !data.laserScanRaw().empty()) applyScanFilter(data, raw.id());
    data.setFeatures({}, {}, cv::Mat());
    data.setLandmarks({});  // carried to the next update's node
    compressForMemory(data);
    in.data = data;
  } else {
    SensorData pose;
    pose.setStamp(raw.stamp());
    pose.setGroundTruth(raw.groundTruth());
    pose.setIMU(raw.imu());
    in.data = pose;
  }
  setFrameOf(in, raw, odom, covariance);
  return in;
}

// RGBD/NeighborLinkRefining: the odometry link to the previous node re-estimated by
// registration (ICP on scans typically), from odometry as guess. Wheel odometry drifts; the
// scans do not, except along what they do not see (a corridor's axis), where
// RGBD/NeighborLinkRefiningPrior keeps the odometry (OdometryPrior.h).
void Rtabmap::Impl::refineNeighborLink(int newId) {
  memory::Memory& memory = detector->memory();
  Signature* current = memory.mutableSignature(newId);
  if (!current) return;
  StageTimer timer(stats, Statistics::kTimingNeighbor_link_refining);
  for (const auto& [to, link] : std::multimap<int, Link>(current->getLinks())) {
    if (link.type() != Link::kNeighbor || to >= newId) continue;
    // After intermediate nodes, the registration is with the node before them (they have no
    // data, or less than a node), and the correction is spread over the chain.
    const std::vector<int> chain = chainToPreviousNode(to);
    if (chain.empty()) continue;
    Signature* previous = memory.mutableSignature(chain.front());
    RegistrationInfo info;
    const Link forward = chain.size() == 1 ? link.inverse() : chainOdometry(chain, newId);  // previous -> new
    Transform t = registration->compute(*previous, *current, forward.transform(), &info);
    if (t.isNull() && registration->usesVision() && registration->usesScans()) {
      // Visual then ICP (Reg/Strategy 2): in a turn the two images share too few features for
      // the visual step, whose only use here is a guess for ICP; the odometry is one already.
      const std::string visualProblem = info.rejectedMsg;
      t = registration->computeIcp(*previous, *current, forward.transform(), &info);
      if (t.isNull()) info.rejectedMsg = visualProblem + "; ICP from the odometry: " + info.rejectedMsg;
    }
    stats.addStatistic(Statistics::kNeighborLinkRefiningAccepted, t.isNull() ? 0.f : 1.f);
    if (t.isNull()) {
      RTABMAP_DEBUG("neighbour link " << to << "->" << newId << " not refined: " << info.rejectedMsg);
      continue;
    }
    stats.addStatistic(Statistics::kNeighborLinkRefiningICP_inliers_ratio, static_cast<float>(info.icpInliersRatio));
    const Link::InfMatrix information = refinedInformation(info, forward, options.covOffDiagIgnored);
    t = fuseWithOdometryPrior(t, information, forward.transform(), options.neighborLinkRefiningPrior);
    if (chain.size() == 1) {
      memory.addLink(Link(to, newId, Link::kNeighbor, t, information));
      const Transform previousPose = graph.pose(to);
      if (!previousPose.isNull()) graph.setPose(newId, mapId, previousPose * t);
    } else {
      spreadOverChain(chain, newId, forward.transform(), t, information);
    }
  }
}

std::vector<int> Rtabmap::Impl::chainToPreviousNode(int previousId) const {
  const memory::Memory& memory = detector->memory();
  std::vector<int> chain{previousId};
  while (true) {
    const Signature* s = memory.signature(chain.back());
    if (!s) return {};
    if (!s->isIntermediate()) break;
    int before = 0;
    for (const auto& [to, link] : s->getLinks()) {
      if (link.type() == Link::kNeighbor && to < s->id()) before = to;
    }
    if (!before) return {};  // the map starts with it (or the rest is in the LTM)
    chain.push_back(before);
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

// The odometry links of the chain composed (Link::compose: each link's noise carried into the
// frame of the whole, not summed as if every link were measured along the same axes).
Link Rtabmap::Impl::chainOdometry(const std::vector<int>& chain, int newId) const {
  const memory::Memory& memory = detector->memory();
  std::optional<Link> whole;
  for (size_t j = 0; j < chain.size(); ++j) {
    const int next = j + 1 < chain.size() ? chain[j + 1] : newId;
    const Signature* s = memory.signature(next);
    for (const auto& [to, link] : s->getLinks()) {
      if (link.type() != Link::kNeighbor || to != chain[j]) continue;
      whole = whole ? whole->compose(link.inverse(), Link::kNeighbor) : link.inverse();
    }
  }
  // chainToPreviousNode() built the chain from these links.
  if (!whole) throw std::logic_error("chainOdometry: no neighbour link along the chain to node " + std::to_string(newId));
  const Link::InfMatrix covariance = whole->infMatrix().inverse();
  return Link(chain.front(), newId, Link::kNeighbor, whole->transform(),
              informationOf(covariance, options.covOffDiagIgnored));
}

// The refined motion from chain[0] to newId, `refined`, replaces the odometry's, `odometry`,
// over the intermediate nodes between them: each gets the share of the correction of the
// distance travelled up to it (linear in translation, slerp in rotation), so the chain composes
// to the refined motion and stays as smooth as the odometry. The refined covariance is split
// over the n links (C/n each: in series they sum to C).
void Rtabmap::Impl::spreadOverChain(const std::vector<int>& chain, int newId, const Transform& odometry,
                                    const Transform& refined, const Link::InfMatrix& information) {
  memory::Memory& memory = detector->memory();
  std::vector<int> nodes = chain;
  nodes.push_back(newId);
  const Transform origin = memory.signature(nodes.front())->getPose();
  std::vector<Transform> relative;  // odometry pose of each node in chain[0]'s frame
  std::vector<double> travelled{0.0};
  for (int id : nodes) relative.push_back(origin.inverse() * memory.signature(id)->getPose());
  for (size_t j = 1; j < nodes.size(); ++j) {
    travelled.push_back(travelled.back() + (relative[j - 1].inverse() * relative[j]).getNorm());
  }
  const double total = travelled.back();
  const Transform correction = refined * odometry.inverse();
  std::vector<Transform> corrected;
  for (size_t j = 0; j < nodes.size(); ++j) {
    const double share = total > 1e-9 ? travelled[j] / total : static_cast<double>(j) / (nodes.size() - 1);
    corrected.push_back(Transform::Identity().interpolate(share, correction) * relative[j]);
  }
  corrected.back() = refined;  // exactly, whatever the rounding
  const Link::InfMatrix split = information * static_cast<double>(nodes.size() - 1);
  const Transform base = graph.pose(nodes.front());
  for (size_t j = 1; j < nodes.size(); ++j) {
    memory.addLink(Link(nodes[j - 1], nodes[j], Link::kNeighbor, corrected[j - 1].inverse() * corrected[j], split));
    if (!base.isNull()) graph.setPose(nodes[j], mapId, base * corrected[j]);
  }
}

std::vector<Link> Rtabmap::Impl::proximityByTime(int newId) {
  if (!options.proximityByTime) return {};
  StageTimer timer(stats, Statistics::kTimingProximity_by_time);
  memory::Memory& memory = detector->memory();
  const ProximityByTimeResult r =
      detectProximityByTime(memory, newId, ramPosesOfGroup(), *registration, options.covOffDiagIgnored);
  for (const Link& l : r.links) {
    memory.addLink(l);
    detector->linksChanged({l.from(), l.to()});
  }
  for (const std::string& why : r.rejections) RTABMAP_DEBUG(why);
  return r.links;
}

std::optional<Link> Rtabmap::Impl::verifyLoopClosure(int newId, int hypothesisId, bool checkDistance,
                                                     std::optional<Link>* refusedForJump) {
  memory::Memory& memory = detector->memory();
  Signature* current = memory.mutableSignature(newId);
  Signature* hypothesis = memory.mutableSignature(hypothesisId);
  if (!current || !hypothesis) return std::nullopt;
  StageTimer timer(stats, Statistics::kTimingHypotheses_validation);
  // Appearance gives no motion guess; ICP alone only refines one (the identity, if the user
  // says loop closures are seen from the same spot).
  const Transform guess = options.loopClosureIdentityGuess ? Transform::Identity() : Transform();
  RegistrationInfo info;
  Transform t;
  if (options.loopClosureReextractFeatures && registration->usesVision()) {
    // Copies without words or cached features: the registration extracts its own from the
    // images, and the nodes keep what they had.
    Signature a = *current, b = *hypothesis;
    for (Signature* s : {&a, &b}) {
      s->setWords({}, {}, {}, cv::Mat());
      s->sensorData().setFeatures({}, {}, cv::Mat());
    }
    t = registration->compute(a, b, guess, &info);
  } else {
    // RGBD/LocalBundleOnLoopClosure: against the hypothesis and its neighbours when it can (a
    // visual-only strategy, a map around the hypothesis), else the two nodes as usual.
    const LocalFeatureMap map = options.localBundleOnLoopClosure && registration->visualOnly()
                                    ? localFeatureMap(memory, hypothesisId)
                                    : LocalFeatureMap{0, {}, {}, {}, "not asked"};
    if (map.problem.empty()) {
      t = registerToLocalMap(map, *current, *registration->visualOnly(), registration->repeatOnce(), guess, &info);
    } else {
      if (options.localBundleOnLoopClosure) RTABMAP_DEBUG("no local bundle for " << hypothesisId << ": " << map.problem);
      t = registration->compute(*current, *hypothesis, guess, &info);
    }
  }
  stats.addStatistic(Statistics::kLoopVisual_matches, static_cast<float>(info.matches));
  stats.addStatistic(Statistics::kLoopVisual_inliers, static_cast<float>(info.inliers));
  if (t.isNull()) {
    RTABMAP_INFO("loop closure " << newId << "->" << hypothesisId << " rejected: " << info.rejectedMsg);
    return std::nullopt;
  }
  Link link(newId, hypothesisId, Link::kGlobalClosure, t, informationOf(info.covariance, options.covOffDiagIgnored));
  if (checkDistance && options.maxLoopClosureDistance > 0.0f) {
    const Transform there = graph.pose(hypothesisId), here = graph.pose(newId);
    if (!there.isNull() && !here.isNull() && graph.sameGroup(graph.mapOf(hypothesisId), mapId)) {
      const double jump = (there * t.inverse()).getDistance(here);
      if (jump > options.maxLoopClosureDistance) {
        RTABMAP_INFO("loop closure " << newId << "->" << hypothesisId << " rejected: it moves the robot by " << jump
                                     << " m, more than " << Parameters::kRGBDMaxLoopClosureDistance() << " "
                                     << options.maxLoopClosureDistance);
        if (refusedForJump) *refusedForJump = link;
        return std::nullopt;
      }
    }
  }
  return link;
}

}  // namespace rtabmap
