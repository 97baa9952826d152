#include "rtabmap_conversions/GraphConversions.h"

#include <gtest/gtest.h>

#include <limits>

using namespace rtabmap_conversions;
using rtabmap::Link;
using rtabmap::Transform;

namespace {

Link::InfMatrix information() {
  Link::InfMatrix inf = Link::InfMatrix::Identity() * 100.0;
  inf(5, 5) = 400.0;
  inf(0, 5) = inf(5, 0) = 3.0;
  return inf;
}

}  // namespace

TEST(GraphConversions, LinkRoundTripsForEveryType) {
  for (int t = 0; t < Link::kTypeCount; ++t) {
    const Link link(3, 8, Link::typeFromInt(t), Transform(1.0, 0.5, 0.0, 0.0, 0.0, 0.3), information());
    const rtabmap_ros::Link msg = linkToMsg(link);
    EXPECT_EQ(msg.type, t);
    EXPECT_EQ(msg.information[5], 3.0);  // row-major (0, 5)
    std::string error;
    const std::optional<Link> back = linkFromMsg(msg, &error);
    ASSERT_TRUE(back) << error;
    EXPECT_EQ(back->from(), 3);
    EXPECT_EQ(back->to(), 8);
    EXPECT_EQ(back->type(), link.type());
    EXPECT_TRUE(back->transform().toEigen().isApprox(link.transform().toEigen(), 1e-12));
    EXPECT_EQ(back->infMatrix(), link.infMatrix());
  }
}

TEST(GraphConversions, BadLinksAreErrors) {
  std::string error;
  rtabmap_ros::Link msg = linkToMsg(Link(1, 2, Link::kNeighbor, Transform::Identity(), information()));
  rtabmap_ros::Link unknown = msg;
  unknown.type = 42;
  EXPECT_FALSE(linkFromMsg(unknown, &error));
  EXPECT_NE(error.find("unknown type 42"), std::string::npos) << error;
  rtabmap_ros::Link nullTransform = msg;
  nullTransform.transform.rotation.w = 0.0;
  EXPECT_FALSE(linkFromMsg(nullTransform, &error));
  EXPECT_NE(error.find("null"), std::string::npos) << error;
  rtabmap_ros::Link nanInfo = msg;
  nanInfo.information[14] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(linkFromMsg(nanInfo, &error));
  EXPECT_NE(error.find("information"), std::string::npos) << error;
}

TEST(GraphConversions, MapGraphRoundTrip) {
  std::map<int, Transform> poses = {{1, Transform::Identity()}, {2, Transform(1, 0, 0.1)}, {5, Transform(2, 1, 1.5)}};
  std::multimap<int, Link> links;
  links.emplace(1, Link(1, 2, Link::kNeighbor, Transform(1, 0, 0.1), information()));
  links.emplace(2, Link(2, 5, Link::kNeighbor, Transform(1, 1, 1.4)));
  links.emplace(5, Link(5, 1, Link::kGlobalClosure, Transform(-2, -1, -1.5)));
  std_msgs::Header header;
  header.frame_id = "map";
  header.stamp = ros::Time(9, 0);
  const Transform mapToOdom(0.1, -0.2, 0.05);
  const rtabmap_ros::MapGraph msg = mapGraphToMsg(poses, links, mapToOdom, header);
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.posesId, (std::vector<int>{1, 2, 5}));
  std::string error;
  const std::optional<MapGraph> back = mapGraphFromMsg(msg, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->poses.size(), 3u);
  EXPECT_TRUE(back->poses.at(5).toEigen().isApprox(poses.at(5).toEigen(), 1e-12));
  EXPECT_TRUE(back->mapToOdom.toEigen().isApprox(mapToOdom.toEigen(), 1e-12));
  ASSERT_EQ(back->links.size(), 3u);
  EXPECT_EQ(back->links.find(5)->second.type(), Link::kGlobalClosure);

  const rtabmap_ros::MapGraph lostMapToOdom = mapGraphToMsg(poses, links, Transform(), header);
  ASSERT_TRUE(mapGraphFromMsg(lostMapToOdom));
  EXPECT_TRUE(mapGraphFromMsg(lostMapToOdom)->mapToOdom.isNull());

  rtabmap_ros::MapGraph mismatched = msg;
  mismatched.posesId.pop_back();
  EXPECT_FALSE(mapGraphFromMsg(mismatched, &error));
  EXPECT_NE(error.find("pose ids"), std::string::npos) << error;
  rtabmap_ros::MapGraph badLink = msg;
  badLink.links[1].type = -7;
  EXPECT_FALSE(mapGraphFromMsg(badLink, &error));
  EXPECT_NE(error.find("link 2 -> 5"), std::string::npos) << error;
  rtabmap_ros::MapGraph nanPose = msg;
  nanPose.poses[0].position.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(mapGraphFromMsg(nanPose, &error));
  EXPECT_NE(error.find("node 1"), std::string::npos) << error;
}
