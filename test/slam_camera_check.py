#!/usr/bin/env python3
"""rostest check (slam_camera.test): the RGB-D demo launch (rgbd_odometry + rtabmap, namespace
rtabmap) on 7-Scenes frames. The optimised poses of the map's nodes (get_map_data) are compared
with the dataset's ground truth at the nodes' stamps after a rigid 3D alignment, and the grid
from the depth images must have free and occupied cells."""
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


def ate3d(estimate, truth):
    """RMSE of 3D positions after the rigid alignment minimising it (Umeyama, no scale)."""
    a, b = np.asarray(estimate, float), np.asarray(truth, float)
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((b - cb).T @ (a - ca))
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    aligned = ((u @ d @ vt) @ (a - ca).T).T + cb
    return float(np.sqrt(np.mean(np.sum((aligned - b) ** 2, axis=1))))


class SlamCameraTest(unittest.TestCase):
    def test_maps_from_the_camera_alone(self):
        folder = common.data_file("rgbd_7scenes")
        if folder is None:
            self.skipTest("rgbd_7scenes not found in ../shared/data (or $RTABMAP_DATA_DIR)")
        frames = int(rospy.get_param("~frames", 450))
        bag = os.path.join(common.workdir(self, "slam_camera_"), "7scenes.bag")
        common.convert(self, "7scenes", folder, bag, "--max-frames", str(frames), "--no-imu")
        with rosbag.Bag(bag) as b:
            truth = sorted((m.header.stamp.to_sec(), m.pose.pose.position)
                           for _, m, _ in b.read_messages(topics=["/ground_truth"]))
        self.assertGreater(len(truth), 0.9 * frames)

        infos, grids = [], []
        rospy.Subscriber(NS + "info", Info, infos.append)
        rospy.Subscriber(NS + "grid_map", OccupancyGrid, grids.append)
        rospy.wait_for_service(NS + "get_map_data", timeout=60.0)
        common.play(self, bag, float(rospy.get_param("~rate", 0.25)), timeout=180)
        common.wait_quiet(infos, quiet=3.0, timeout=30.0)

        data = rospy.ServiceProxy(NS + "get_map_data", GetMap)(True, True, False).data
        stamps = {n.id: n.stamp for n in data.nodes}
        poses = dict(zip(data.graph.posesId, data.graph.poses))
        self.assertGreaterEqual(len(poses), 8, "too few nodes: %d" % len(poses))
        truth_stamps = np.array([s for s, _ in truth])
        estimate, reference = [], []
        for node_id, pose in poses.items():
            i = int(np.argmin(np.abs(truth_stamps - stamps[node_id])))
            self.assertLess(abs(truth_stamps[i] - stamps[node_id]), 0.02, "node %d has no ground truth" % node_id)
            estimate.append([pose.position.x, pose.position.y, pose.position.z])
            p = truth[i][1]
            reference.append([p.x, p.y, p.z])
        path = float(np.sum(np.linalg.norm(np.diff(np.array(reference), axis=0), axis=1)))
        error = ate3d(estimate, reference)
        print("slam_camera: %d nodes over %.2f m of ground truth, ATE %.4f m, %d updates"
              % (len(poses), path, error, len(infos)), file=sys.stderr)
        self.assertGreater(path, 1.0, "the excerpt barely moves")
        self.assertLess(error, 0.08)

        self.assertTrue(grids, "no grid_map")
        cells = np.array(grids[-1].data)
        self.assertGreater(np.sum(cells == 0), 100, "no free cell in the grid from depth")
        self.assertGreater(np.sum(cells == 100), 20, "no obstacle in the grid from depth")


if __name__ == "__main__":
    rospy.init_node("slam_camera_check")
    rostest.rosrun(common.PKG, "slam_camera", SlamCameraTest, sys.argv)
