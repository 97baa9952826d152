#!/usr/bin/env python3
"""rostest check (slam_stereo.test): the stereo demo launch on EuRoC frames. The map's nodes
(get_map_data) carry a stereo camera model and visual words with 3D points in front of the
robot, their optimised positions stay on the Vicon ground truth, and the grid from the disparity
has free and occupied cells."""
import os
import sys
import unittest

import numpy as np
import rosbag
import rospy
import rostest
from nav_msgs.msg import OccupancyGrid

from rtabmap_ros.msg import Info
from rtabmap_ros.srv import GetMap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import odom_common as common  # noqa: E402

NS = "/rtabmap/"


class SlamStereoTest(unittest.TestCase):
    def test_maps_from_the_stereo_pair(self):
        folder = common.data_file("euroc_v1_01_micro")
        if folder is None:
            self.skipTest("euroc_v1_01_micro not found in ../shared/data (or $RTABMAP_DATA_DIR)")
        frames = int(rospy.get_param("~frames", 95))
        bag = os.path.join(common.workdir(self, "slam_stereo_"), "euroc.bag")
        common.convert(self, "euroc", folder, bag, "--max-frames", str(frames), "--no-imu")
        with rosbag.Bag(bag) as b:
            truth = sorted((m.header.stamp.to_sec(), m.pose.pose.position)
                           for _, m, _ in b.read_messages(topics=["/ground_truth"]))
        self.assertGreater(len(truth), 0.9 * frames)

        infos, grids = [], []
        rospy.Subscriber(NS + "info", Info, infos.append)
        rospy.Subscriber(NS + "grid_map", OccupancyGrid, grids.append)
        rospy.wait_for_service(NS + "get_map_data", timeout=60.0)
        common.play(self, bag, float(rospy.get_param("~rate", 0.25)), timeout=120)
        common.wait_quiet(infos, quiet=3.0, timeout=30.0)

        data = rospy.ServiceProxy(NS + "get_map_data", GetMap)(True, True, False).data
        poses = dict(zip(data.graph.posesId, data.graph.poses))
        nodes = {n.id: n for n in data.nodes}
        self.assertGreaterEqual(len(poses), 5, "too few nodes: %d" % len(poses))
        with_words = [n for n in nodes.values() if len(n.wordIds) >= 50]
        self.assertGreaterEqual(len(with_words), len(poses) // 2, "nodes without visual words")
        for n in with_words:
            self.assertGreater(n.baseline, 0.05, "node %d has no stereo camera model" % n.id)
            # 3D of the words from the disparity: finite, at room distances (the Vicon room is a
            # few metres across), not at the camera.
            pts = np.array([[p.x, p.y, p.z] for p in n.wordPts])
            finite = pts[np.all(np.isfinite(pts), axis=1)]
            self.assertGreater(len(finite), 0.5 * len(pts), "node %d: words without 3D" % n.id)
            distance = float(np.median(np.linalg.norm(finite, axis=1)))
            self.assertTrue(0.5 < distance < 10.0, "node %d: words at %.2f m" % (n.id, distance))

        truth_stamps = np.array([s for s, _ in truth])
        origin = None
        worst = 0.0
        for node_id, pose in sorted(poses.items()):
            i = int(np.argmin(np.abs(truth_stamps - nodes[node_id].stamp)))
            self.assertLess(abs(truth_stamps[i] - nodes[node_id].stamp), 0.02, "node %d has no ground truth" % node_id)
            p = truth[i][1]
            moved = np.array([p.x, p.y, p.z])
            if origin is None:
                origin = moved
            # The MAV moves under 2 cm: each node must stay within a few cm of the first.
            estimate = np.array([pose.position.x, pose.position.y, pose.position.z])
            worst = max(worst, float(np.linalg.norm(estimate - (moved - origin))))
        print("slam_stereo: %d nodes (%d with words), %d updates, worst position error %.4f m"
              % (len(poses), len(with_words), len(infos), worst), file=sys.stderr)
        self.assertLess(worst, 0.05)

        self.assertTrue(grids, "no grid_map")
        cells = np.array(grids[-1].data)
        self.assertGreater(np.sum(cells == 0), 20, "no free cell in the grid from disparity")
        self.assertGreater(np.sum(cells == 100), 5, "no obstacle in the grid from disparity")


if __name__ == "__main__":
    rospy.init_node("slam_stereo_check")
    rostest.rosrun(common.PKG, "slam_stereo", SlamStereoTest, sys.argv)
