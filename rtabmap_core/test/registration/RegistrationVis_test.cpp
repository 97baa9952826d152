// Visual registration of two rendered frames with a known relative pose, through every path:
// PnP and 3D-3D, with and without guess, optical flow, backward averaging, bundle adjustment,
// on nodes (Signature) and on prepared frames; and its rejections.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "odometry/SyntheticRoom.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/memory/Memory.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/registration/RegistrationVis.h"

namespace rtabmap {
namespace {

using test::SyntheticRoom;

const Transform kFrom(0.0, 0.2, 1.1, 0.0, 0.0, 0.3);
const Transform kMotion(0.12, -0.05, 0.02, 0.01, 0.03, 0.08);  // from -> to
// How close an RGB-D registration of the rendered pair comes to kMotion: a pixel is about a
// centimetre at the room's 2.6 m at this resolution (320 x 240). Over 31 textures of the room
// the worst was 1.3 cm, the median about 0.8 cm.
constexpr double kMetres = 0.015;
constexpr double kRadians = 0.005;

struct Pair {
  SensorData from, to;
};

Pair renderPair(bool stereo = false, const Transform& motion = kMotion) {
  static const SyntheticRoom room;
  if (stereo) {
    const StereoCameraModel m = SyntheticRoom::stereoCamera();
    return {room.stereo(kFrom, m, 1), room.stereo(kFrom * motion, m, 2)};
  }
  const CameraModel m = SyntheticRoom::camera();
  return {room.rgbd(kFrom, m, 1), room.rgbd(kFrom * motion, m, 2)};
}

void expectNear(const Transform& found, const Transform& truth, double metres, double radians) {
  ASSERT_FALSE(found.isNull());
  EXPECT_LT(found.getDistance(truth), metres) << found.prettyPrint() << " vs " << truth.prettyPrint();
  EXPECT_LT((found.inverse() * truth).getAngle(), radians);
}

Transform registerNodes(const ParametersMap& p, const Transform& guess, RegistrationInfo* info, bool stereo = false) {
  const Pair pair = renderPair(stereo);
  Signature a(pair.from), b(pair.to);
  RegistrationVis reg(p);
  return reg.computeTransform(a, b, guess, info);
}

TEST(RegistrationVis, PnPWithAndWithoutGuess) {
  for (const Transform& guess : {Transform(), Transform::Identity(), kMotion * Transform(0.02, 0.01, 0, 0, 0, 0.01)}) {
    RegistrationInfo info;
    const Transform t = registerNodes({}, guess, &info);
    SCOPED_TRACE(guess.isNull() ? "no guess" : guess.prettyPrint());
    expectNear(t, kMotion, kMetres, kRadians);
    EXPECT_TRUE(info.success);
    EXPECT_TRUE(info.rejectedMsg.empty());
    EXPECT_GE(info.inliers, 100);
    EXPECT_GE(info.matches, info.inliers);
    EXPECT_EQ(static_cast<int>(info.inliersIDs.size()), info.inliers);
    EXPECT_GT(info.inliersDistribution, 0.1);
    EXPECT_GT(info.inliersMeanDistance, 1.0);
    EXPECT_GT(info.covariance(0, 0), 0.0);
    EXPECT_LT(info.covariance(0, 0), 1e-3);
  }
}

TEST(RegistrationVis, ThreeDToThreeD) {
  RegistrationInfo info;
  expectNear(registerNodes({{"Vis/EstimationType", "0"}, {"Vis/InlierDistance", "0.05"}}, Transform(), &info), kMotion,
             kMetres, kRadians);
}

TEST(RegistrationVis, OpticalFlowWithAndWithout3DTo3D) {
  for (const char* estimation : {"1", "0"}) {
    RegistrationInfo info;
    const ParametersMap p{{"Vis/CorType", "1"}, {"Vis/EstimationType", estimation}, {"Vis/InlierDistance", "0.05"}};
    const Transform t = registerNodes(p, Transform::Identity(), &info);
    SCOPED_TRACE(std::string("Vis/EstimationType ") + estimation);
    expectNear(t, kMotion, kMetres, kRadians);
    EXPECT_GT(info.inliers, 100);
  }
}

// Without a guess, optical flow starts each point where it was: after a large motion only part of
// the points are tracked, some onto look-alike patches. The first pass's transform then predicts
// where each point went, and tracking again from there keeps the whole set.
TEST(RegistrationVis, OpticalFlowWithoutGuessTracksAgainFromTheFirstEstimate) {
  const Transform large(0.15, -0.05, 0.02, 0.02, 0.03, 0.16);
  const Pair pair = renderPair(false, large);
  Signature a(pair.from), b(pair.to);
  RegistrationVis reg(ParametersMap{{"Vis/CorType", "1"}});
  RegistrationInfo info;
  const Transform t = reg.computeTransform(a, b, Transform(), &info);
  expectNear(t, large, kMetres, kRadians);
  // Over 10 textures of the room: 347-400 inliers, at most 5 mm off; the first pass alone kept
  // 56-271 inliers, up to 2 cm off.
  EXPECT_GE(info.inliers, 300);
}

TEST(RegistrationVis, BackwardAveragingAndBundleAdjustment) {
  RegistrationInfo info;
  {
    SCOPED_TRACE("backward");
    expectNear(registerNodes({{"Vis/ForwardEstOnly", "false"}}, Transform(), &info), kMotion, kMetres, kRadians);
  }
  {
    SCOPED_TRACE("bundle adjustment");
    expectNear(registerNodes({{"Vis/BundleAdjustment", "3"}}, Transform(), &info), kMotion, kMetres, kRadians);
  }
}

TEST(RegistrationVis, StereoFrames) {
  RegistrationInfo info;
  expectNear(registerNodes({}, Transform(), &info, true), kMotion, 0.015, 0.006);
  EXPECT_GT(info.inliers, 60);
}

TEST(RegistrationVis, NodesKeepTheirExtractedFeatures) {
  const Pair pair = renderPair();
  Signature a(pair.from), b(pair.to);
  ASSERT_TRUE(a.sensorData().keypoints().empty());
  RegistrationVis reg;
  RegistrationInfo info;
  expectNear(reg.computeTransform(a, b, Transform(), &info), kMotion, kMetres, kRadians);
  EXPECT_FALSE(a.sensorData().keypoints().empty());
  EXPECT_EQ(a.sensorData().descriptors().rows, static_cast<int>(a.sensorData().keypoints().size()));
  // Only compressed images left: the stored features are reused, nothing to uncompress.
  SensorData compressedOnly = a.sensorData();
  compressedOnly.compress(".png");
  compressedOnly.clearRaw();
  a.setSensorData(compressedOnly);
  expectNear(reg.computeTransform(a, b, Transform(), &info), kMotion, kMetres, kRadians);
  // The reverse registration is the inverse.
  expectNear(reg.computeTransform(b, a, Transform(), &info), kMotion.inverse(), kMetres, kRadians);
}

TEST(RegistrationVis, WordsOfANodeAreUsedWithTheirIds) {
  const Pair pair = renderPair();
  RegistrationVis reg;
  const ImageFeatures f = reg.detector().extract(pair.from);
  Signature a(pair.from), b(pair.to);
  std::multimap<int, int> words;
  for (size_t i = 0; i < f.size(); ++i) words.emplace(1000 + static_cast<int>(i), static_cast<int>(i));
  a.setWords(words, f.keypoints, f.points3D, f.descriptors);
  RegistrationInfo info;
  expectNear(reg.computeTransform(a, b, Transform(), &info), kMotion, kMetres, kRadians);
  for (int id : info.inliersIDs) EXPECT_GE(id, 1000);
}

// Mem/RawDescriptorsKept false: the memory keeps the words of a location without their
// descriptors, and two such nodes are registered by pairing their words by id.
TEST(RegistrationVis, WordsWithoutDescriptorsArePairedById) {
  const Pair pair = renderPair();
  RegistrationVis reg;
  memory::MemoryOptions o;
  o.rawDescriptorsKept = false;
  o.rehearsalSimilarity = 1.0f;  // two locations, not one merged
  memory::Memory m(o);
  std::vector<int> ids;
  for (const SensorData* data : {&pair.from, &pair.to}) {
    const ImageFeatures f = reg.detector().extract(*data);
    memory::LocationInput in;
    in.keypoints = f.keypoints;
    in.descriptors = f.descriptors;
    in.points3D = f.points3D;
    in.data = *data;
    ids.push_back(m.addLocation(in).id);
  }
  Signature a = *m.signature(ids[0]), b = *m.signature(ids[1]);
  for (const Signature* s : {&a, &b}) {
    ASSERT_GT(s->getWords().size(), 100u);
    EXPECT_TRUE(s->getWordsDescriptors().empty());
  }
  // Words in both nodes, once in each: the most pairs there can be.
  std::map<int, int> count;
  for (const Signature* s : {&a, &b}) {
    for (const auto& [word, index] : s->getWords()) count[word] += s->getWords().count(word) == 1 ? 1 : 100;
  }
  const int pairable = static_cast<int>(std::count_if(count.begin(), count.end(), [](const auto& c) { return c.second == 2; }));
  RegistrationInfo info;
  expectNear(reg.computeTransform(a, b, Transform(), &info), kMotion, kMetres, kRadians);
  EXPECT_EQ(info.matches, pairable);
  EXPECT_GE(info.inliers, 50);
  for (int id : info.inliersIDs) EXPECT_EQ(count[id], 2) << "word " << id;
  EXPECT_TRUE(a.sensorData().keypoints().empty()) << "nothing extracted again";
  // A guess limits the pairs to the Vis/CorGuessWinSize window around each projection: the
  // true motion keeps nearly all, one 0.3 m and 0.2 rad off very few.
  RegistrationInfo guided, misguided;
  expectNear(reg.computeTransform(a, b, kMotion, &guided), kMotion, kMetres, kRadians);
  EXPECT_GE(guided.matches, info.inliers);
  reg.computeTransform(a, b, kMotion * Transform(0.3, 0, 0, 0, 0, 0.2), &misguided);
  EXPECT_LT(misguided.matches, guided.matches / 4);
  // With a node that has no words, descriptors are matched: extracted again from the images.
  Signature c(pair.to);
  expectNear(reg.computeTransform(a, c, Transform(), &info), kMotion, kMetres, kRadians);
  EXPECT_FALSE(a.sensorData().keypoints().empty());
}

TEST(RegistrationVis, RejectionsSayWhy) {
  const Pair pair = renderPair();
  // Textureless new frame.
  cv::Mat flat(pair.to.imageRaw().size(), CV_8UC3, cv::Scalar(90, 90, 90));
  Signature a(pair.from), b(SensorData(flat, pair.to.depthOrRightRaw(), pair.to.cameraModels()[0], 2));
  RegistrationVis reg;
  RegistrationInfo info;
  EXPECT_TRUE(reg.computeTransform(a, b, Transform(), &info).isNull());
  EXPECT_FALSE(info.success);
  EXPECT_NE(info.rejectedMsg.find("no features"), std::string::npos) << info.rejectedMsg;
  // Unrelated views: the opposite walls.
  static const SyntheticRoom room;
  Signature c(room.rgbd(Transform(0, 0, 1.2, 0, 0, M_PI), SyntheticRoom::camera(), 3));
  EXPECT_TRUE(reg.computeTransform(a, c, Transform(), &info).isNull());
  EXPECT_TRUE(info.rejectedMsg.find("Vis/MinInliers") != std::string::npos ||
              info.rejectedMsg.find("no consistent pose") != std::string::npos)
      << info.rejectedMsg;
  // Descriptors of another type.
  RegistrationVis sift(ParametersMap{{"Vis/FeatureType", "1"}});
  const VisualFrame orbFrame = VisualFrame::fromSensorData(pair.from, reg.detector().extract(pair.from));
  const VisualFrame siftFrame = VisualFrame::fromSensorData(pair.to, sift.detector().extract(pair.to));
  EXPECT_TRUE(reg.computeTransform(orbFrame, siftFrame, Transform(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("differ"), std::string::npos) << info.rejectedMsg;
  // A required spread of the inliers no frame can meet.
  RegistrationVis picky(ParametersMap{{"Vis/MinInliersDistribution", "0.45"}});
  Signature d(pair.from), e(pair.to);
  EXPECT_TRUE(picky.computeTransform(d, e, Transform(), &info).isNull());
  EXPECT_NE(info.rejectedMsg.find("Vis/MinInliersDistribution"), std::string::npos) << info.rejectedMsg;
}

TEST(RegistrationVis, OptionsValidation) {
  EXPECT_THROW(RegistrationVis(ParametersMap{{"Vis/MinDepth", "3"}, {"Vis/MaxDepth", "2"}}), ParameterError);
  RegistrationVisOptions o;
  o.bundleAdjustment = 1;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("Vis/BundleAdjustment"), std::string::npos);
}

}  // namespace
}  // namespace rtabmap
