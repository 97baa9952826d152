#!/usr/bin/python3
"""Checks odom_services.test: while the ACES excerpt plays, pause_odom / resume_odom stop and
restart the updates, reset_odom_to_pose and reset_odom restart at the asked pose, and
odom_local_map / odom_last_frame publish non-empty clouds in the odometry frame; the bag
played again from its start (ROS time back) restarts odometry at the origin."""
import math
import os
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rtabmap_ros.srv import ResetPose
from sensor_msgs.msg import PointCloud2
from std_srvs.srv import Empty

import odom_common as oc

MOVE = 0.5  # m the robot may move between a reset and the next update


class OdomServices(unittest.TestCase):
    def test_services_while_playing(self):
        log = oc.data_file("radish/aces.clf.bz2", shipped=True)
        if log is None:
            self.skipTest("radish/aces.clf.bz2 not found (../shared/data or data/)")
        bag = os.path.join(oc.workdir(self, "rtabmap_odom_services_"), "aces.bag")
        oc.convert(self, "carmen", log, bag, "--max-frames", str(rospy.get_param("~frames", 250)))

        odoms, local_maps, last_frames = [], [], []
        sub = rospy.Subscriber("/icp_odom", Odometry, odoms.append, queue_size=1000)
        rospy.Subscriber("/odom_local_map", PointCloud2, local_maps.append, queue_size=10)
        rospy.Subscriber("/odom_last_frame", PointCloud2, last_frames.append, queue_size=10)
        for name in ("reset_odom", "pause_odom", "resume_odom", "reset_odom_to_pose"):
            rospy.wait_for_service("/" + name, timeout=30)
        reset = rospy.ServiceProxy("/reset_odom", Empty)
        pause = rospy.ServiceProxy("/pause_odom", Empty)
        resume = rospy.ServiceProxy("/resume_odom", Empty)
        reset_to = rospy.ServiceProxy("/reset_odom_to_pose", ResetPose)
        self.assertTrue(oc.wait_for(lambda: sub.get_num_connections() > 0, 30))

        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", str(rospy.get_param("~rate", 2)), bag],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            self.assertTrue(oc.wait_for(lambda: len(odoms) >= 20, 30), "no odometry while playing")
            pause()
            time.sleep(0.5)  # an update already under way may still come out
            paused_at = len(odoms)
            time.sleep(2.0)
            self.assertEqual(len(odoms), paused_at, "odometry published while paused")
            resume()
            self.assertTrue(oc.wait_for(lambda: len(odoms) >= paused_at + 5, 10), "no odometry after resume_odom")

            n = len(odoms)
            reset_to(x=10.0, y=-3.0, z=0.0, roll=0.0, pitch=0.0, yaw=1.0)
            self.assertTrue(oc.wait_for(lambda: len(odoms) >= n + 3, 10))
            p = odoms[-1].pose.pose
            yaw = 2 * math.atan2(p.orientation.z, p.orientation.w)
            self.assertLess(math.hypot(p.position.x - 10.0, p.position.y + 3.0), MOVE, f"pose after reset_odom_to_pose {p}")
            self.assertLess(abs(yaw - 1.0), 0.3)

            n = len(odoms)
            reset()
            self.assertTrue(oc.wait_for(lambda: len(odoms) >= n + 3, 10))
            p = odoms[-1].pose.pose
            self.assertLess(math.hypot(p.position.x, p.position.y), MOVE, f"pose after reset_odom {p}")
        finally:
            player.terminate()
            player.wait(timeout=10)

        # The bag played again from its start (ROS time jumps back): odometry restarts at the
        # origin, not at the pose it had (moved far away first, so the two cannot be confused).
        reset_to(x=20.0, y=20.0, z=0.0, roll=0.0, pitch=0.0, yaw=0.0)
        n = len(odoms)
        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", str(rospy.get_param("~rate", 2)), bag],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            self.assertTrue(oc.wait_for(lambda: len(odoms) >= n + 3, 30), "no odometry after the bag restarted")
        finally:
            player.terminate()
            player.wait(timeout=10)
        p = odoms[n].pose.pose
        self.assertLess(math.hypot(p.position.x, p.position.y), MOVE, f"first pose after the bag restarted {p}")

        self.assertGreater(len(local_maps), 0, "odom_local_map not published")
        self.assertGreater(len(last_frames), 0, "odom_last_frame not published")
        for cloud in (local_maps[-1], last_frames[-1]):
            self.assertEqual(cloud.header.frame_id, "icp_odom")
            self.assertGreater(cloud.width * cloud.height, 50)


if __name__ == "__main__":
    rospy.init_node("odom_services_check")
    rostest.rosrun(oc.PKG, "odom_services", OdomServices, sys.argv)
