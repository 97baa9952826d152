#!/usr/bin/env python3
"""Checks slam_lidar3d.test: 3D lidar SLAM end to end. icp_odometry follows the simulated
VLP-16 with the wheel guess (few lost frames, ATE well below the wheel odometry's), and the
rtabmap node on the same clouds builds a graph that closes the loop by proximity, an occupancy
grid from the 3D local grids, and map -> icp_odom in tf. An IMU filter's orientation on
/imu/data (published here, level, from an IMU mounted upside down on the base) gives each node
a level gravity link. A landmark detector's output (published here on landmark_detection from the
ground truth: a marker 1.5 m ahead of the start, seen within 3 m) gives the nodes near the start,
at the tour's beginning and end, landmark links to it, and mapGraph its pose."""
import math
import os
import subprocess
import sys
import threading
import time
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import OccupancyGrid, Odometry
from sensor_msgs.msg import Imu

from rtabmap_ros.msg import Info, LandmarkDetection, MapGraph

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import odom_common as common  # noqa: E402  (bag conversion and playing, ATE)

PKG = "rtabmap_ros"


def by_stamp(store):
    return lambda m: store.__setitem__(m.header.stamp.to_nsec(), m)


class SlamLidar3dTest(unittest.TestCase):
    def setUp(self):
        self.odoms, self.info, self.graphs, self.grids = [], [], [], []
        self.truth, self.wheel = {}, {}
        rospy.Subscriber("/rtabmap/odom", Odometry, self.odoms.append, queue_size=1000)
        rospy.Subscriber("/rtabmap/info", Info, self.info.append, queue_size=100)
        rospy.Subscriber("/rtabmap/mapGraph", MapGraph, self.graphs.append, queue_size=10)
        rospy.Subscriber("/rtabmap/grid_map", OccupancyGrid, self.grids.append, queue_size=10)
        self.landmark, self.detections = None, 0
        self.landmark_pub = rospy.Publisher("/rtabmap/landmark_detection", LandmarkDetection, queue_size=100)
        rospy.Subscriber("/ground_truth", Odometry, self.publish_landmark, queue_size=1000)
        rospy.Subscriber("/ground_truth", Odometry, by_stamp(self.truth), queue_size=1000)
        rospy.Subscriber("/odom", Odometry, by_stamp(self.wheel), queue_size=1000)
        self.tf_buffer = tf2_ros.Buffer(rospy.Duration(600.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)

    def make_bag(self):
        folder = common.workdir(self, "slam_lidar3d_")
        sim, bag = os.path.join(folder, "sim"), os.path.join(folder, "lidar3d.bag")
        r = subprocess.run(["rosrun", PKG, "rtabmap-sim", "--scenario", "loop", "--rate", "2", "--no-rgbd",
                            "--no-urg", "--no-utm", "--lidar3d", "--output", sim],
                           capture_output=True, text=True, timeout=240)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        common.convert(self, "sim", sim + "?scan=lidar", bag, "--no-imu")
        return bag

    def publish_imu(self, stop):
        """An IMU filter's output at each new ROS time (the bag's /clock): the robot is level,
        the IMU upside down under it (imu_link, roll pi), so its own orientation is roll pi."""
        static = tf2_ros.StaticTransformBroadcaster()
        mount = TransformStamped()
        mount.header.frame_id, mount.child_frame_id = "base_link", "imu_link"
        mount.transform.translation.z = -0.1
        mount.transform.rotation.x, mount.transform.rotation.w = 1.0, 0.0
        static.sendTransform(mount)
        pub = rospy.Publisher("/imu/data", Imu, queue_size=100)
        last = rospy.Time(0)
        while not stop.is_set():
            now = rospy.Time.now()
            if now > last:
                m = Imu()
                m.header.stamp, m.header.frame_id = now, "imu_link"
                m.orientation.x, m.orientation.w = 1.0, 0.0
                m.linear_acceleration.z = -9.81
                m.angular_velocity_covariance[0] = m.linear_acceleration_covariance[0] = 0.01
                pub.publish(m)
                last = now
            time.sleep(0.005)

    def publish_landmark(self, truth):
        """Landmark 3, fixed 1.5 m ahead of where the robot starts (0.5 m up, turned as the robot
        started), as a detector on the robot would see it: its pose in base_link at the stamp of
        each ground-truth pose within 3 m of it, covariance left to Marker/Variance*."""
        p, q = truth.pose.pose.position, truth.pose.pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        if self.landmark is None:
            self.landmark = (p.x + 1.5 * math.cos(yaw), p.y + 1.5 * math.sin(yaw), yaw)
        lx, ly, lyaw = self.landmark
        dx, dy = lx - p.x, ly - p.y
        if math.hypot(dx, dy) > 3.0:
            return
        d = LandmarkDetection()
        d.header.stamp, d.header.frame_id = truth.header.stamp, "base_link"
        d.id, d.size = 3, 0.2
        d.pose.pose.position.x = math.cos(yaw) * dx + math.sin(yaw) * dy
        d.pose.pose.position.y = -math.sin(yaw) * dx + math.cos(yaw) * dy
        d.pose.pose.position.z = 0.5
        d.pose.pose.orientation.z, d.pose.pose.orientation.w = math.sin(0.5 * (lyaw - yaw)), math.cos(0.5 * (lyaw - yaw))
        self.landmark_pub.publish(d)
        self.detections += 1

    def test_lidar3d_slam_on_simulated_loop(self):
        bag = self.make_bag()
        started = time.time()
        stop = threading.Event()
        imu = threading.Thread(target=self.publish_imu, args=(stop,), daemon=True)
        imu.start()
        try:
            common.play(self, bag, rospy.get_param("~rate", 2), timeout=240)
        finally:
            stop.set()
            imu.join()
        common.wait_quiet(self.info, quiet=3.0, timeout=60.0)
        rospy.loginfo("bag played in %.1f s wall: %d odom, %d info, %d mapGraph, %d grid_map",
                      time.time() - started, len(self.odoms), len(self.info), len(self.graphs), len(self.grids))
        self.check_odometry()
        self.check_graph()
        self.check_grid()
        self.assertTrue(self.tf_buffer.can_transform("map", "icp_odom", rospy.Time(0)), "no map -> icp_odom in tf")

    def check_odometry(self):
        clouds = len(self.truth)
        self.assertGreater(clouds, 300, "the bag has too few frames")
        self.assertGreaterEqual(len(self.odoms), 0.9 * clouds, f"{len(self.odoms)} odometry updates for {clouds} clouds")
        lost = [m for m in self.odoms if common.lost(m)]
        self.assertLessEqual(len(lost), 0.02 * len(self.odoms), f"{len(lost)} lost frames")
        icp, truth, wheel = [], [], []
        for m in self.odoms:
            s = m.header.stamp.to_nsec()
            if common.lost(m) or s not in self.truth or s not in self.wheel:
                continue
            self.assertEqual((m.header.frame_id, m.child_frame_id), ("icp_odom", "base_link"))
            icp.append((m.pose.pose.position.x, m.pose.pose.position.y))
            t, w = self.truth[s].pose.pose.position, self.wheel[s].pose.pose.position
            truth.append((t.x, t.y))
            wheel.append((w.x, w.y))
        ate_icp, ate_wheel = common.ate(icp, truth), common.ate(wheel, truth)
        rospy.loginfo("icp_odometry ATE %.3f m on %d frames (wheel odometry %.3f m)", ate_icp, len(icp), ate_wheel)
        # Offline (rtabmap-dataset --odom s2m, same clouds and guess): 0.033 m.
        self.assertLess(ate_icp, 0.15)
        self.assertLess(ate_icp, 0.5 * ate_wheel)

    def check_graph(self):
        self.assertGreater(len(self.info), 20, "too few SLAM updates on info")
        self.assertTrue(self.graphs, "no mapGraph")
        graph = self.graphs[-1]
        ids = set(graph.posesId)
        self.assertGreater(len(ids), 20)
        self.assertTrue(all(l.fromId in ids and l.toId in ids for l in graph.links), "link to an unknown node")
        loops = [l for l in graph.links if l.type in (1, 2)]  # global loop closure, proximity in space
        rospy.loginfo("mapGraph: %d nodes, %d links, %d loop closure / proximity", len(ids), len(graph.links),
                      len(loops))
        self.assertGreater(len(loops), 0, "the tour's end was not linked to its start")
        # Gravity links (type 9, a node to itself) from /imu/data, brought to the base: level.
        gravity = {l.fromId: l.transform.rotation for l in graph.links if l.type == 9 and l.fromId == l.toId}
        rospy.loginfo("gravity links on %d of %d nodes", len(gravity), len(ids))
        self.assertGreaterEqual(len(gravity), 0.9 * len(ids), "nodes without the IMU's gravity link")
        for node, q in gravity.items():
            tilt = 2.0 * math.asin(min(1.0, math.hypot(q.x, q.y)))  # angle of the up axis from vertical
            self.assertLess(tilt, 1e-3, f"node {node}'s gravity link is tilted {tilt:.3f} rad (imu_link not applied?)")
        # Landmark 3 (type 8 links, node -3 in mapGraph): seen when leaving and again when back.
        seen = sorted(l.fromId for l in graph.links if l.type == 8 and l.toId == -3)
        rospy.loginfo("landmark 3: %d detections published, seen from %d nodes (%s)", self.detections, len(seen), seen)
        self.assertGreater(self.detections, 0, "no ground truth near the start to publish landmark detections from")
        self.assertGreaterEqual(len(seen), 2, "landmark_detection did not reach the nodes")
        self.assertIn(-3, ids, "mapGraph has no pose for the landmark")
        self.assertGreater(seen[-1] - seen[0], 20, "seen at the tour's start only, not again at its end")
        # The optimised nodes against the ground truth at their stamps.
        stamps = {i.refId: i.header.stamp.to_nsec() for i in self.info}
        slam, truth = [], []
        for node, pose in zip(graph.posesId, graph.poses):
            s = stamps.get(node)
            if s in self.truth:
                slam.append((pose.position.x, pose.position.y))
                t = self.truth[s].pose.pose.position
                truth.append((t.x, t.y))
        self.assertGreater(len(slam), 20, "too few nodes matched to ground-truth stamps")
        ate_slam = common.ate(slam, truth)
        rospy.loginfo("SLAM ATE %.3f m on %d nodes", ate_slam, len(slam))
        self.assertLess(ate_slam, 0.15)

    def check_grid(self):
        self.assertTrue(self.grids, "no grid_map")
        grid = self.grids[-1]
        self.assertEqual(grid.header.frame_id, "map")
        free, occupied = common.grid_cells(grid)
        rospy.loginfo("grid_map %dx%d at %.2f m: %d free, %d occupied", grid.info.width, grid.info.height,
                      grid.info.resolution, free, occupied)
        # A 21-room building at 10 cm cells: thousands of free cells, walls as obstacles.
        self.assertGreater(free, 2000)
        self.assertGreater(occupied, 300)


if __name__ == "__main__":
    rospy.init_node("slam_lidar3d_check")
    rostest.rosrun(PKG, "slam_lidar3d", SlamLidar3dTest, sys.argv)
