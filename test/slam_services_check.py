#!/usr/bin/env python3
"""rostest check of the rtabmap node's goal, map-data and map-editing interface
(slam_services.test): makes a bag of the simulator's `loop` scenario with rtabmap-sim, plays the
first part, sets goals and queries the map, plays the rest (the robot comes back to the start,
where the goal is), then edits the map and switches databases."""
import copy
import math
import os
import sys
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path as NavPath
from std_msgs.msg import Bool
from std_srvs.srv import Empty
from visualization_msgs.msg import Marker, MarkerArray

from rtabmap_ros.msg import Goal, Info, Link, MapData, MapGraph, Path
from rtabmap_ros.srv import (AddLink, GetMap, GetNodeData, GetNodesInRadius, GetPlan, ListLabels, LoadDatabase,
                             PublishMap, RemoveLabel, SetGoal, SetLabel)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fault_common as fault  # noqa: E402  (the simulator bag)
import odom_common as common  # noqa: E402  (temporary folders, bag playing, waiting)

PKG = "rtabmap_ros"


def position(pose):
    return (pose.position.x, pose.position.y, pose.position.z)


def distance(a, b):
    return math.dist(position(a), position(b))


def yaw(pose):
    q = pose.orientation
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def markers(array, ns):
    return [m for m in array.markers if m.ns == ns and m.action == Marker.ADD]


class SlamServicesTest(unittest.TestCase):
    def setUp(self):
        self.info, self.graphs, self.map_data, self.reached = [], [], [], []
        self.map_paths, self.global_paths, self.path_nodes = [], [], []
        self.labels, self.graph_markers = [], []
        for topic, kind, out in [("/info", Info, self.info), ("/mapGraph", MapGraph, self.graphs),
                                 ("/mapData", MapData, self.map_data), ("/goal_reached", Bool, self.reached),
                                 ("/mapPath", NavPath, self.map_paths), ("/global_path", NavPath, self.global_paths),
                                 ("/global_path_nodes", Path, self.path_nodes), ("/labels", MarkerArray, self.labels),
                                 ("/graph_markers", MarkerArray, self.graph_markers)]:
            rospy.Subscriber(topic, kind, out.append)
        self.goal_pub = rospy.Publisher("/goal", PoseStamped, queue_size=1)
        self.goal_node_pub = rospy.Publisher("/goal_node", Goal, queue_size=1)

    # ------------------------------------------------------------------ helpers
    def make_bag(self, duration):
        return fault.make_sim_bag(self, common.workdir(self, "slam_services_"), duration)

    def play(self, bag, start, duration=None):
        """rosbag play --clock of [start, start + duration) s of the bag, then waits for the node."""
        common.play(self, bag, rospy.get_param("~rate", 6), start=start, duration=duration)
        common.wait_quiet(self.info, quiet=3.0, timeout=30.0)

    def call(self, name, srv_type, *args, **kwargs):
        rospy.wait_for_service(name, timeout=10.0)
        return rospy.ServiceProxy(name, srv_type)(*args, **kwargs)

    def refused(self, name, srv_type, *args, **kwargs):
        """A bad request: the service answers false (rospy raises ServiceException)."""
        with self.assertRaises(rospy.ServiceException, msg=f"{name} accepted {args} {kwargs}"):
            self.call(name, srv_type, *args, **kwargs)

    def wait_latest(self, messages, predicate, what, timeout=10.0):
        ok = common.wait_for(lambda: messages and predicate(messages[-1]), timeout)
        self.assertTrue(ok, f"{what} (last of {len(messages)} messages: "
                            f"{messages[-1] if messages and len(str(messages[-1])) < 400 else '...'})")
        return messages[-1]

    def whole_map(self, optimized=True, graph_only=True, whole=True):
        return self.call("/get_map_data", GetMap, whole, optimized, graph_only).data

    # ------------------------------------------------------------------ the test
    def test_services_on_simulated_loop(self):
        bag = self.make_bag(rospy.get_param("~duration", 180))
        split = rospy.get_param("~split", 90)
        started = time.time()
        self.play(bag, 0, split)
        self.assertTrue(self.graphs, "no mapGraph")
        graph = self.graphs[-1]
        poses = dict(zip(graph.posesId, graph.poses))
        first = graph.posesId[0]
        rospy.loginfo("first part played in %.1f s wall: %d nodes", time.time() - started, len(poses))
        self.assertGreater(len(poses), 20)

        self.check_incremental_map_data(poses)
        self.check_labels(poses, first)
        self.check_goals(poses, first)
        self.check_plans(poses, first)
        self.check_nodes_in_radius(poses, first)
        self.check_node_data(first)
        self.check_map_data(poses)
        self.check_bad_requests(first)

        # The goal for the second part: the start, where the loop ends.
        path = self.call("/set_goal", SetGoal, first, "", "")
        self.assertEqual(path.path_ids[-1], first)
        self.play(bag, split)
        rospy.loginfo("whole bag played in %.1f s wall", time.time() - started)
        self.assertTrue(common.wait_for(lambda: any(m.data for m in self.reached), 5.0),
                        f"goal_reached never true ({[m.data for m in self.reached]})")
        self.wait_latest(self.map_paths, lambda m: not m.poses, "mapPath not cleared when the goal was reached")
        self.check_loop_closure_markers()
        self.check_add_link()
        self.check_remove_label(first)
        self.check_update_parameters()
        self.check_load_database()
        rospy.loginfo("done in %.1f s wall", time.time() - started)

    # ------------------------------------------------------------------ after the first part
    def check_incremental_map_data(self, poses):
        """mapData after each update: the graph and the data of the node of that update."""
        with_nodes = [m for m in self.map_data if m.nodes]
        self.assertGreater(len(with_nodes), 10, "too few mapData with a node")
        ids = [m.nodes[0].id for m in with_nodes]
        self.assertTrue(all(len(m.nodes) == 1 for m in with_nodes), "mapData is incremental: one node per update")
        # An update that only rehearses the previous node (robot still) sends that node again.
        self.assertEqual(ids, sorted(ids), "nodes in the order they were added")
        self.assertGreater(len(set(ids)), 10)
        self.assertTrue(set(ids) <= set(poses), "mapData sent a node the graph does not have")
        last = with_nodes[-1]
        self.assertGreater(len(last.nodes[0].image), 0, "no image in the node data")
        self.assertGreater(len(last.nodes[0].laserScan), 0, "no scan in the node data")
        self.assertIn(last.nodes[0].id, last.graph.posesId)

    def check_labels(self, poses, first):
        self.call("/set_label", SetLabel, "start", first)
        array = self.wait_latest(self.labels, lambda a: any(m.text == "start" for m in markers(a, "labels")),
                                 "no 'start' text marker on labels")
        m = next(m for m in markers(array, "labels") if m.text == "start")
        self.assertEqual(m.type, Marker.TEXT_VIEW_FACING)
        self.assertEqual(array.markers[0].action, Marker.DELETEALL)
        self.assertAlmostEqual(m.pose.position.x, poses[first].position.x, places=3)
        self.assertAlmostEqual(m.pose.position.y, poses[first].position.y, places=3)

        array = self.wait_latest(self.graph_markers, lambda a: markers(a, "nodes"), "no graph_markers")
        nodes = markers(array, "nodes")[0]
        self.assertEqual(nodes.type, Marker.SPHERE_LIST)
        self.assertEqual(len(nodes.points), len(poses))
        neighbours = markers(array, "neighbor")
        self.assertTrue(neighbours and neighbours[0].type == Marker.LINE_LIST)
        self.assertGreaterEqual(len(neighbours[0].points), 2 * (len(poses) - 1) - 2)

    def check_path_topics(self, goal_id, goal_pose):
        nodes = self.wait_latest(self.path_nodes, lambda m: m.nodeIds and m.nodeIds[-1] == goal_id,
                                 f"global_path_nodes does not end at node {goal_id}")
        path = self.wait_latest(self.map_paths, lambda m: len(m.poses) == len(nodes.nodeIds),
                                "mapPath is not the path of global_path_nodes")
        self.assertEqual(path.header.frame_id, "map")
        self.assertLess(distance(path.poses[-1].pose, goal_pose), 1e-3, "mapPath does not end at the goal node")
        self.wait_latest(self.global_paths, lambda m: len(m.poses) == len(nodes.nodeIds), "global_path differs")
        return nodes

    def check_goals(self, poses, first):
        res = self.call("/set_goal", SetGoal, 0, "start", "")
        rospy.loginfo("set_goal 'start': %d nodes in %.4f s", len(res.path_ids), res.planning_time)
        self.assertGreater(len(res.path_ids), 1)
        self.assertEqual(res.path_ids[-1], first)
        self.assertEqual(len(res.path_poses), len(res.path_ids))
        self.assertGreaterEqual(res.planning_time, 0.0)
        nodes = self.check_path_topics(first, poses[first])
        self.assertEqual(list(nodes.nodeIds), list(res.path_ids))

        self.call("/cancel_goal", Empty)
        self.wait_latest(self.map_paths, lambda m: not m.poses, "cancel_goal did not empty mapPath")
        self.wait_latest(self.path_nodes, lambda m: not m.nodeIds, "cancel_goal did not empty global_path_nodes")

        ids = sorted(poses)
        by_id = ids[len(ids) // 3]
        self.goal_node_pub.publish(Goal(node_id=by_id))
        self.check_path_topics(by_id, poses[by_id])
        self.goal_node_pub.publish(Goal(node_label="start"))
        self.check_path_topics(first, poses[first])

        # A pose goal goes to the nearest node.
        by_pose = ids[len(ids) // 2]
        goal = PoseStamped()
        goal.header.frame_id = "map"
        goal.pose = copy.deepcopy(poses[by_pose])
        goal.pose.position.x += 0.05
        self.goal_pub.publish(goal)
        self.check_path_topics(by_pose, poses[by_pose])
        self.call("/cancel_goal", Empty)
        self.wait_latest(self.map_paths, lambda m: not m.poses, "cancel_goal did not empty mapPath")

    def check_plans(self, poses, first):
        """get_plan answers a plan and leaves the active goal alone."""
        self.call("/set_goal", SetGoal, first, "", "")
        self.check_path_topics(first, poses[first])
        goal_paths = len(self.path_nodes)
        ids = sorted(poses)
        target = ids[len(ids) // 2]
        plan = self.call("/get_plan", GetPlan, target, PoseStamped(), 0.0).plan
        self.assertGreater(len(plan.poses), 1)
        self.assertEqual(plan.header.frame_id, "map")
        self.assertLess(distance(plan.poses[-1].pose, poses[target]), 1e-3)
        goal = PoseStamped()
        goal.header.frame_id = "map"
        goal.pose = copy.deepcopy(poses[target])
        goal.pose.position.y += 0.2
        plan = self.call("/get_plan", GetPlan, 0, goal, 0.5).plan
        self.assertLess(distance(plan.poses[-1].pose, goal.pose), 1e-3, "the plan ends at the goal pose")
        self.assertLess(distance(plan.poses[-2].pose, poses[target]), 1e-3, "through the nearest node")
        self.refused("/get_plan", GetPlan, 0, goal, 0.1)  # the nearest node is 0.2 m away
        time.sleep(0.5)
        self.assertEqual(len(self.path_nodes), goal_paths, "get_plan published a path")
        self.assertEqual(self.path_nodes[-1].nodeIds[-1], first, "get_plan changed the goal")
        self.call("/cancel_goal", Empty)

    def check_nodes_in_radius(self, poses, first):
        res = self.call("/get_nodes_in_radius", GetNodesInRadius, first, 0, 0, 0, 1.5, 0)
        expected = {i for i, p in poses.items() if distance(p, poses[first]) <= 1.5}
        self.assertEqual(set(res.ids), expected)
        self.assertEqual(res.ids[0], first, "nearest first")
        self.assertEqual(len(res.poses), len(res.ids))
        p = poses[first].position
        res = self.call("/get_nodes_in_radius", GetNodesInRadius, 0, p.x + 0.01, p.y, p.z, 0.0, 1)
        self.assertEqual(list(res.ids), [first], "k = 1 nearest of a position")
        self.refused("/get_nodes_in_radius", GetNodesInRadius, 99999, 0, 0, 0, 1.0, 0)

    def check_node_data(self, first):
        full = self.call("/get_node_data", GetNodeData, [first], True, True, True, True).data
        self.assertEqual([n.id for n in full], [first])
        n = full[0]
        self.assertGreater(len(n.image), 0)
        self.assertGreater(len(n.depth), 0)
        self.assertGreater(len(n.laserScan), 0)
        self.assertGreater(len(n.grid_obstacles) + len(n.grid_ground), 0, "no local grid")
        self.assertEqual(n.label, "start")
        bare = self.call("/get_node_data", GetNodeData, [first], False, False, False, False).data[0]
        self.assertEqual((len(bare.image), len(bare.depth), len(bare.laserScan), len(bare.grid_obstacles)),
                         (0, 0, 0, 0))
        self.assertGreater(len(bare.fx), 0, "the calibration comes with any node data")
        self.refused("/get_node_data", GetNodeData, [first, 99999], True, False, False, False)
        self.refused("/get_node_data", GetNodeData, [], True, False, False, False)

    def check_map_data(self, poses):
        graph_only = self.whole_map()
        self.assertEqual(set(graph_only.graph.posesId), set(poses))
        self.assertEqual(len(graph_only.nodes), 0, "graphOnly carries no node data")
        ends = set(graph_only.graph.posesId)
        self.assertGreater(len(graph_only.graph.links), len(poses) - 2)
        self.assertTrue(all(l.fromId in ends and l.toId in ends for l in graph_only.graph.links))
        for i, p in zip(graph_only.graph.posesId, graph_only.graph.poses):
            self.assertLess(distance(p, poses[i]), 1e-4, "optimised poses are mapGraph's")

        with_data = self.whole_map(graph_only=False)
        self.assertEqual(sorted(n.id for n in with_data.nodes), sorted(poses))
        self.assertTrue(all(len(n.image) > 0 for n in with_data.nodes), "a node without its image")

        odometry = self.whole_map(optimized=False)
        self.assertEqual(set(odometry.graph.posesId), set(poses))
        wm = self.whole_map(whole=False)
        self.assertTrue(set(wm.graph.posesId) <= set(poses))

        count = len(self.map_data)
        self.call("/publish_map", PublishMap, True, True, False)
        self.assertTrue(common.wait_for(lambda: len(self.map_data) > count, 5.0), "publish_map published nothing")
        published = self.map_data[-1]
        self.assertEqual(sorted(n.id for n in published.nodes), sorted(poses))
        self.assertEqual(len(published.graph.posesId), len(poses))

    def check_bad_requests(self, first):
        self.refused("/set_goal", SetGoal, 99999, "", "")
        self.refused("/set_goal", SetGoal, 0, "", "")
        self.refused("/set_goal", SetGoal, 0, "nowhere", "")
        self.refused("/get_plan", GetPlan, 99999, PoseStamped(), 0.0)
        self.refused("/remove_label", RemoveLabel, "")
        self.refused("/remove_label", RemoveLabel, "nowhere")
        link = Link(fromId=first, toId=99999, type=4)
        link.transform.rotation.w = 1.0
        link.information = [100.0 if i % 7 == 0 else 0.0 for i in range(36)]
        self.refused("/add_link", AddLink, link)
        link.toId, link.information = first + 1, [0.0] * 36
        self.refused("/add_link", AddLink, link)  # no information
        self.refused("/load_database", LoadDatabase, "", False)

    # ------------------------------------------------------------------ after the second part
    def check_loop_closure_markers(self):
        array = self.wait_latest(self.graph_markers, lambda a: markers(a, "loop_closure") or markers(a, "proximity"),
                                 "no loop-closure or proximity line in graph_markers")
        lines = markers(array, "loop_closure") + markers(array, "proximity")
        self.assertTrue(all(m.type == Marker.LINE_LIST and len(m.points) >= 2 for m in lines))
        rospy.loginfo("graph_markers: %s", {m.ns: len(m.points) for m in array.markers if m.ns})

    def check_add_link(self):
        graph = self.whole_map().graph
        poses = dict(zip(graph.posesId, graph.poses))
        a, b = graph.posesId[0], graph.posesId[len(graph.posesId) // 2]
        self.assertFalse(any({l.fromId, l.toId} == {a, b} for l in graph.links))
        # The transform the map already has between them (2D), 10 cm / 0.1 rad uncertainty.
        pa, pb = poses[a], poses[b]
        dx, dy, t = pb.position.x - pa.position.x, pb.position.y - pa.position.y, yaw(pa)
        link = Link(fromId=a, toId=b, type=4)
        link.transform.translation.x = math.cos(t) * dx + math.sin(t) * dy
        link.transform.translation.y = -math.sin(t) * dx + math.cos(t) * dy
        rel = yaw(pb) - t
        link.transform.rotation.z, link.transform.rotation.w = math.sin(rel / 2), math.cos(rel / 2)
        link.information = [100.0 if i % 7 == 0 else 0.0 for i in range(36)]
        self.call("/add_link", AddLink, link)
        graph = self.whole_map().graph
        users = [l for l in graph.links if l.type == 4]
        self.assertTrue(any({l.fromId, l.toId} == {a, b} for l in users), "the user link is not in the map")

    def check_remove_label(self, first):
        self.call("/remove_label", RemoveLabel, "start")
        self.assertNotIn("start", self.call("/list_labels", ListLabels).labels)
        self.wait_latest(self.labels, lambda a: all(m.text != "start" for m in markers(a, "labels")),
                         "the removed label is still drawn")
        self.refused("/set_goal", SetGoal, 0, "start", "")

    def node_count(self):
        return len(self.whole_map(optimized=False).graph.posesId)

    def check_update_parameters(self):
        """update_parameters re-reads the private Group/Name parameters and restarts the core on
        the same database: Mem/IncrementalMemory false makes it a localization node (the map is
        read-only: set_label refused), true a mapping node again; an invalid value is warned and
        ignored, the map is kept."""
        nodes = self.node_count()
        some = self.whole_map(optimized=False).graph.posesId[0]
        rospy.set_param("/rtabmap/RGBD/LocalRadius", "-1")
        self.call("/update_parameters", Empty)
        self.assertEqual(self.node_count(), nodes, "update_parameters did not reopen the same database")
        rospy.delete_param("/rtabmap/RGBD/LocalRadius")
        rospy.set_param("/rtabmap/Mem/IncrementalMemory", "false")
        self.call("/update_parameters", Empty)
        self.refused("/set_label", SetLabel, "read-only", some)
        self.assertEqual(self.node_count(), nodes)
        rospy.set_param("/rtabmap/Mem/IncrementalMemory", "true")
        self.call("/update_parameters", Empty)
        rospy.delete_param("/rtabmap/Mem/IncrementalMemory")
        self.call("/set_label", SetLabel, "writable", some)
        self.assertIn("writable", self.call("/list_labels", ListLabels).labels)
        self.assertEqual(self.node_count(), nodes)

    def check_load_database(self):
        nodes = self.node_count()
        # load_database only opens files in database_directory (default: database_path's).
        other = os.path.join(os.path.dirname(rospy.get_param("/rtabmap/database_path")),
                             "slam_services_other_%d.db" % os.getpid())
        for suffix in ("", "-wal", "-shm", "-journal"):
            self.addCleanup(lambda p=other + suffix: os.path.exists(p) and os.remove(p))
        self.call("/load_database", LoadDatabase, other, True)
        self.assertEqual(self.node_count(), 0, "a new database has no node")
        self.assertTrue(os.path.exists(other))
        self.call("/load_database", LoadDatabase, rospy.get_param("/rtabmap/database_path"), False)
        self.assertEqual(self.node_count(), nodes, "the first database lost nodes")


if __name__ == "__main__":
    rospy.init_node("slam_services_check")
    rostest.rosrun(PKG, "slam_services", SlamServicesTest, sys.argv)
