#!/usr/bin/env python3
"""rostest check of slam_nodelet.test: the rtabmap nodelet in a manager on laser + odom topic,
and a badly configured second instance in the same manager."""
import os
import subprocess
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import OccupancyGrid
from nav_msgs.srv import GetMap
from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import Info, MapGraph
from rtabmap_ros.srv import ListLabels

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import odom_common as common  # noqa: E402  (bag playing, temporary folders, waiting)

PKG = "rtabmap_ros"


class SlamNodeletTest(unittest.TestCase):
    def setUp(self):
        self.info, self.graphs, self.logs, self.assembled = [], [], [], []
        rospy.Subscriber("/assembler/grid_map", OccupancyGrid, self.assembled.append)
        rospy.Subscriber("/info", Info, self.info.append)
        rospy.Subscriber("/mapGraph", MapGraph, self.graphs.append)
        rospy.Subscriber("/rosout", Log, self.logs.append)

    def make_bag(self):
        folder = common.workdir(self, "slam_nodelet_")
        bag = os.path.join(folder, "loop.bag")
        r = subprocess.run(["rosrun", PKG, "rtabmap-sim", "--scenario", "loop", "--rate", "2", "--width", "160",
                            "--height", "120", "--no-stereo", "--no-urg", "--texture-size", "64", "--duration",
                            str(rospy.get_param("~duration", 60)), "--output", os.path.join(folder, "sim"),
                            "--bag", bag], capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        return bag

    def logged(self, level, *words):
        return any(m.level == level and all(w in m.msg for w in words) for m in self.logs)

    def test_bad_instance_then_mapping(self):
        self.assertTrue(common.wait_for(lambda: self.logged(Log.ERROR, "/proc/no_such_dir/rtabmap.db"), 20.0),
                        "no error about the database that cannot be created")
        self.assertTrue(self.logged(Log.WARN, "Reg/Stratgy", "Reg/Strategy"), "no warning naming the closest key")
        self.assertTrue(self.logged(Log.WARN, "frame_idd", "\"frame_id\""), "no warning naming frame_id")
        rospy.wait_for_service("/bad/get_map", timeout=5.0)
        with self.assertRaises(rospy.ServiceException):
            rospy.ServiceProxy("/bad/get_map", GetMap)()
        with self.assertRaises(rospy.ServiceException):
            rospy.ServiceProxy("/bad/list_labels", ListLabels)()

        # The good instance maps the bag from the scans and the odom topic.
        common.play(self, self.make_bag(), rospy.get_param("~rate", 5), timeout=60)
        common.wait_quiet(self.info, quiet=3.0, timeout=20.0)
        self.assertGreater(len(self.info), 20, "too few SLAM updates")
        self.assertTrue(self.graphs)
        graph = self.graphs[-1]
        self.assertGreater(len(graph.posesId), 20)
        neighbours = [l for l in graph.links if l.type == 0]
        rospy.loginfo("laser + odom topic: %d updates, %d nodes, %d links (%d neighbour)", len(self.info),
                      len(graph.posesId), len(graph.links), len(neighbours))
        self.assertGreaterEqual(len(neighbours), len(graph.posesId) - 1, "nodes not chained by odometry links")
        # The odom topic's covariance reached the links: finite, positive information.
        for l in neighbours:
            self.assertTrue(all(v == v for v in l.information))
            self.assertGreater(l.information[0], 0.0)

        # The map_assembler nodelet (same manager) followed the updates: its grid is of the
        # graph's last update and shows the walls and the free space between them.
        self.assertTrue(common.wait_for(lambda: self.assembled and
                                        self.assembled[-1].header.stamp >= graph.header.stamp, 10.0),
                        "the map_assembler nodelet did not publish the last update's grid")
        grid = self.assembled[-1]
        free, occupied = common.grid_cells(grid)
        rospy.loginfo("map_assembler nodelet: grid %dx%d, %d occupied, %d free cells", grid.info.width,
                      grid.info.height, occupied, free)
        self.assertEqual(grid.header.frame_id, "map")
        self.assertGreater(occupied, 100)
        self.assertGreater(free, 1000)


if __name__ == "__main__":
    rospy.init_node("slam_nodelet_check")
    rostest.rosrun(PKG, "slam_nodelet", SlamNodeletTest, sys.argv)
