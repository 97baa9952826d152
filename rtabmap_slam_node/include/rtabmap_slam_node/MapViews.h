#pragma once
// Views of the map the SLAM nodelet publishes for navigation and for stock rviz, computed from
// the core's plain data (unit-tested without a master): the goal path as nav_msgs/Path, the
// labels and the pose graph as visualization_msgs/MarkerArray, and the nodes near a place.
#include <nav_msgs/Path.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap_slam_node {

using NodePath = std::vector<std::pair<int, rtabmap::Transform>>;

// The path's poses, each taken from `poses` (the latest optimised ones) when the node is there,
// else the pose it was planned with: a loop closure after planning moves the path with the map.
NodePath refreshPath(const NodePath& path, const std::map<int, rtabmap::Transform>& poses);
nav_msgs::Path pathToMsg(const NodePath& path, const std_msgs::Header& header);

// One TEXT_VIEW_FACING marker per label at its node's pose (labels of nodes without a pose in
// `poses`, e.g. of another referential, are left out), after a DELETEALL so that removed labels
// disappear from rviz. Marker ids are the node ids; namespace "labels".
visualization_msgs::MarkerArray labelMarkers(const std::map<int, std::string>& labels,
                                             const std::map<int, rtabmap::Transform>& poses,
                                             const std_msgs::Header& header);

// The pose graph for rviz's MarkerArray display, after a DELETEALL: the nodes as one
// SPHERE_LIST (namespace "nodes"), the landmarks (negative ids: markers) as one CUBE_LIST
// ("landmarks", orange), and the links between ends with poses as one LINE_LIST per kind, each
// its colour, so a kind can be toggled in rviz: "neighbor" (odometry, also merged neighbours;
// blue), "loop_closure" (global loop closures; red), "proximity" (in space or time; yellow),
// "user" (user and virtual links; cyan), "landmark" (a node to a landmark it saw; magenta).
// Empty kinds have no marker.
visualization_msgs::MarkerArray graphMarkers(const std::map<int, rtabmap::Transform>& poses,
                                             const std::multimap<int, rtabmap::Link>& links,
                                             const std_msgs::Header& header);
// The namespace a link type is drawn in ("" = not drawn: pose priors, gravity).
std::string graphMarkerNamespace(rtabmap::Link::Type type);

// Nodes within `radius` (3D distance; <= 0: any distance) of `center`, nearest first, the k
// nearest only when k > 0.
NodePath nodesInRadius(const std::map<int, rtabmap::Transform>& poses, const rtabmap::Transform& center,
                       double radius, int k);

}  // namespace rtabmap_slam_node
