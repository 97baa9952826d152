#!/usr/bin/python3
"""Converts the first scans of the ACES CARMEN log with rtabmap-bag, plays the bag with
`rosbag play --clock`, and checks what a SLAM node would see: monotonic /clock equal to the
data's times, every message of /scan, /odom and /tf (as many as `rosbag info` lists), odometry
that agrees with tf, a latched /tf_static that a late subscriber still receives, and tf able to
place each scan in the odom frame at its stamp. Skips when the log is absent."""
import os
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rospkg
import rospy
import rostest
import tf2_ros
from rosgraph_msgs.msg import Clock
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage

PKG = "rtabmap_ros"


def aces_log():
    """The ACES log: $RTABMAP_DATA_DIR, ../shared/data beside the package, or the shipped copy."""
    root = rospkg.RosPack().get_path(PKG)
    candidates = []
    if os.environ.get("RTABMAP_DATA_DIR"):
        candidates.append(os.path.join(os.environ["RTABMAP_DATA_DIR"], "radish", "aces.clf.bz2"))
    real = os.path.realpath(root)
    candidates += [os.path.join(real, "..", "shared", "data", "radish", "aces.clf.bz2"),
                   os.path.join(real, "data", "radish", "aces.clf.bz2")]
    return next((c for c in candidates if os.path.exists(c)), None)


class BagPlay(unittest.TestCase):
    def test_play_with_clock(self):
        log = aces_log()
        if log is None:
            self.skipTest("radish/aces.clf.bz2 not found (../shared/data or data/)")
        frames = int(rospy.get_param("~frames", 300))
        rate = float(rospy.get_param("~rate", 10))
        workdir = tempfile.mkdtemp(prefix="rtabmap_bag_play_")
        bag = os.path.join(workdir, "aces.bag")
        convert = subprocess.run(["rosrun", PKG, "rtabmap-bag", "--json", "--format", "carmen",
                                  "--max-frames", str(frames), log, bag],
                                 capture_output=True, text=True, timeout=120)
        self.assertEqual(convert.returncode, 0, convert.stdout + convert.stderr)

        with rosbag.Bag(bag) as b:
            in_bag = {t: i.message_count for t, i in b.get_type_and_topic_info().topics.items()}
        self.assertEqual(sorted(in_bag), ["/odom", "/scan", "/tf", "/tf_static"])

        clocks, scans, odoms, tfs, statics = [], [], [], [], []
        rospy.Subscriber("/clock", Clock, lambda m: clocks.append(m.clock), queue_size=10000)
        rospy.Subscriber("/scan", LaserScan, scans.append, queue_size=10000)
        rospy.Subscriber("/odom", Odometry, odoms.append, queue_size=10000)
        rospy.Subscriber("/tf", TFMessage, tfs.append, queue_size=10000)
        tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(3600))
        listener = tf2_ros.TransformListener(tf_buffer)
        time.sleep(1.0)  # let the subscriptions register before the player advertises

        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", str(rate), bag],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        # A late subscriber, once playing has begun: only latching can give it the mountings.
        time.sleep(2.0)
        late = rospy.Subscriber("/tf_static", TFMessage, statics.append)
        _, err = player.communicate(timeout=150)
        self.assertEqual(player.returncode, 0, err)
        time.sleep(1.0)
        late.unregister()
        del listener

        self.assertEqual(len(scans), frames, "every scan of the bag is played")
        self.assertEqual(len(scans), in_bag["/scan"])
        self.assertEqual(len(odoms), in_bag["/odom"])
        self.assertEqual(len(tfs), in_bag["/tf"])
        self.assertGreater(len(clocks), frames)
        self.assertTrue(all(a <= b for a, b in zip(clocks, clocks[1:])), "/clock went back in time")
        stamps = [s.header.stamp for s in scans]
        self.assertTrue(all(a < b for a, b in zip(stamps, stamps[1:])), "scan stamps are not increasing")
        # /clock is the data's own time: it starts at or before the first scan and reaches the
        # last one within its publishing step (rosbag play sends /clock at 100 Hz of wall time,
        # i.e. rate / 100 s of bag time, and may stop before the last message's exact time).
        self.assertLessEqual(clocks[0], stamps[0])
        self.assertGreaterEqual(clocks[-1].to_sec(), stamps[-1].to_sec() - max(1.0, rate / 100.0 * 2))

        self.assertGreaterEqual(len(statics), 1, "/tf_static was not latched for a late subscriber")
        self.assertIn("laser", [t.child_frame_id for t in statics[0].transforms])
        for scan in scans:
            self.assertEqual(scan.header.frame_id, "laser")
            t = tf_buffer.lookup_transform("odom", "laser", scan.header.stamp, rospy.Duration(0))
            self.assertEqual(t.header.frame_id, "odom")
        # /odom and tf odom -> base_link are the same wheel odometry, stamp by stamp.
        for odom in odoms[:: max(1, len(odoms) // 50)]:
            self.assertEqual((odom.header.frame_id, odom.child_frame_id), ("odom", "base_link"))
            t = tf_buffer.lookup_transform("odom", "base_link", odom.header.stamp, rospy.Duration(0))
            p, q = odom.pose.pose.position, t.transform.translation
            self.assertAlmostEqual(p.x, q.x, places=9)
            self.assertAlmostEqual(p.y, q.y, places=9)
            self.assertAlmostEqual(odom.pose.pose.orientation.z, t.transform.rotation.z, places=9)


if __name__ == "__main__":
    rospy.init_node("bag_play_check")
    rostest.rosrun(PKG, "bag_play", BagPlay, sys.argv)
