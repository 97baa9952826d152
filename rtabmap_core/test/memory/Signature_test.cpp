#include <gtest/gtest.h>

#include <stdexcept>

#include "rtabmap_core/memory/Signature.h"

namespace rtabmap {
namespace {

Link neighbor(int from, int to) { return Link(from, to, Link::kNeighbor, Transform(1, 0, 0, 0, 0, 0)); }

TEST(Signature, AddLinkKeepsOneLinkPerNodeAndType) {
  Signature s(5);
  EXPECT_TRUE(s.isLinksModified());
  s.setLinksModified(false);
  s.addLink(neighbor(5, 4));
  s.addLink(Link(5, 4, Link::kGlobalClosure, Transform::Identity()));
  s.addLink(neighbor(5, 4));  // replaces the first
  EXPECT_TRUE(s.isLinksModified());
  EXPECT_EQ(2u, s.getLinks().size());
  EXPECT_TRUE(s.hasLink(4));
  EXPECT_TRUE(s.hasLink(4, Link::kGlobalClosure));
  EXPECT_FALSE(s.hasLink(4, Link::kLocalSpaceClosure));
  EXPECT_EQ(Link::kNeighbor, s.link(4, Link::kNeighbor)->type());
  EXPECT_EQ(nullptr, s.link(9));
  EXPECT_THROW(s.addLink(neighbor(6, 4)), std::invalid_argument);

  EXPECT_EQ(1, s.removeLink(4, Link::kGlobalClosure));
  EXPECT_TRUE(s.hasLink(4, Link::kNeighbor));
  EXPECT_EQ(0, s.removeLink(4, Link::kGlobalClosure));
  EXPECT_EQ(1, s.removeLink(4));
  EXPECT_TRUE(s.getLinks().empty());
}

TEST(Signature, LinksBetweenNodesStayConsistent) {
  Signature a(1), b(2);
  const Link link(1, 2, Link::kNeighbor, Transform(1, 0, 0, 0, 0, M_PI / 2));
  addLinkBetween(a, b, link);
  ASSERT_TRUE(a.hasLink(2, Link::kNeighbor));
  ASSERT_TRUE(b.hasLink(1, Link::kNeighbor));
  EXPECT_EQ(2, b.link(1)->from());
  EXPECT_EQ(1, b.link(1)->to());
  EXPECT_LT((b.link(1)->transform() * link.transform()).getNorm(), 1e-12);
  EXPECT_THROW(addLinkBetween(b, a, link), std::invalid_argument);

  // A self link (pose prior) is added once.
  addLinkBetween(a, a, Link(1, 1, Link::kPosePrior, Transform::Identity()));
  EXPECT_TRUE(a.hasLink(1, Link::kPosePrior));
  EXPECT_EQ(2u, a.getLinks().size());
  // Neighbor links exclude self and landmark links.
  a.addLink(Link(1, -5, Link::kLandmark, Transform::Identity()));
  EXPECT_EQ((std::vector<int>{2}), [&] {
    std::vector<int> ids;
    for (const auto& entry : a.getNeighborLinks()) ids.push_back(entry.first);
    return ids;
  }());

  removeLinkBetween(a, b);
  EXPECT_FALSE(a.hasLink(2));
  EXPECT_FALSE(b.hasLink(1));
  EXPECT_TRUE(a.hasLink(1, Link::kPosePrior));
}

TEST(Signature, ChangeLinkIdsRenamesTheOtherEnd) {
  Signature s(3);
  s.addLink(neighbor(3, 2));
  s.addLink(Link(3, 2, Link::kGlobalClosure, Transform::Identity()));
  s.changeLinkIds(2, 7);
  EXPECT_FALSE(s.hasLink(2));
  EXPECT_TRUE(s.hasLink(7, Link::kNeighbor));
  EXPECT_TRUE(s.hasLink(7, Link::kGlobalClosure));
  EXPECT_EQ(7, s.link(7)->to());
  EXPECT_EQ(2, s.removeLinks());
}

TEST(Signature, WordsAreValidatedAndIndexed) {
  Signature s(1);
  EXPECT_TRUE(s.isBadSignature());  // no words
  const std::multimap<int, int> words{{10, 0}, {11, 1}, {10, 2}};  // word 10 twice
  std::vector<cv::KeyPoint> kpts(3, cv::KeyPoint(1.0f, 2.0f, 3.0f));
  std::vector<cv::Point3f> pts(3, cv::Point3f(1, 2, 3));
  s.setWords(words, kpts, pts, cv::Mat::zeros(3, 32, CV_8UC1));
  EXPECT_FALSE(s.isBadSignature());
  EXPECT_EQ((std::vector<int>{10, 11, 10}), s.wordIdPerKeypoint());
  s.setBadSignature(true);
  EXPECT_TRUE(s.isBadSignature());
  s.setBadSignature(false);

  s.changeWordsRef(10, 20);
  EXPECT_EQ((std::vector<int>{20, 11, 20}), s.wordIdPerKeypoint());
  EXPECT_EQ(0u, s.getWords().count(10));

  EXPECT_THROW(s.setWords(words, std::vector<cv::KeyPoint>(2), pts, cv::Mat()), std::invalid_argument);
  EXPECT_THROW(s.setWords(words, kpts, pts, cv::Mat::zeros(2, 32, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(s.setWords({{1, 0}, {2, 0}, {3, 1}}, kpts, pts, cv::Mat()), std::invalid_argument);
  EXPECT_THROW(s.setWords({{1, 0}, {2, 5}, {3, 1}}, {}, {}, cv::Mat()), std::invalid_argument);
  // Keypoints, points and descriptors are optional.
  EXPECT_NO_THROW(s.setWords(words, {}, {}, cv::Mat()));
  s.removeAllWords();
  EXPECT_TRUE(s.isWordsEmpty());
}

TEST(Signature, FlagsFollowChanges) {
  Signature s(4, 1, 0, 2.0, "", Transform::Identity());
  EXPECT_FALSE(s.isSaved());
  s.setSaved(true);
  s.setModified(false);
  s.setWeight(0);
  EXPECT_FALSE(s.isModified());  // same value
  s.setWeight(3);
  EXPECT_TRUE(s.isModified());
  s.setModified(false);
  s.setLabel("door");
  EXPECT_TRUE(s.isModified());
  EXPECT_EQ("door", s.label());
  EXPECT_EQ(4, s.sensorData().id());
  s.setId(9);
  EXPECT_EQ(9, s.sensorData().id());
  EXPECT_FALSE(s.getVelocity());
  s.setVelocity({1, 0, 0, 0, 0, 0});
  EXPECT_TRUE(s.getVelocity());
  EXPECT_GT(s.memoryUsed(), sizeof(Signature) - 1);
}

TEST(Signature, FromSensorData) {
  SensorData data(LaserScan(), 12, 3.5);
  data.setOdom(Transform(1, 2, 0, 0, 0, 0), Eigen::Matrix<double, 6, 6>::Identity());
  const Signature s(data);
  EXPECT_EQ(12, s.id());
  EXPECT_EQ(3.5, s.stamp());
  EXPECT_EQ(Transform(1, 2, 0, 0, 0, 0), s.getPose());
}

}  // namespace
}  // namespace rtabmap
