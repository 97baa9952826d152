#!/usr/bin/python3
"""Checks sync_missing_topic.test: the 5-second warning of the shared synchroniser, in a
standalone node (topic missing) and in a nodelet manager (topics present, stamps apart)."""
import sys
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import RGBDImage, RGBDImages
from sensor_msgs.msg import CameraInfo, Image

import sync_common as sc

WARNING = "did not receive data since 5 seconds"


class MissingTopic(unittest.TestCase):
    def setUp(self):
        self.log = sc.RosoutLog()
        self.rgb = rospy.Publisher("/missing/rgb/image", Image, queue_size=10)
        self.info = rospy.Publisher("/missing/rgb/camera_info", CameraInfo, queue_size=10)
        self.cams = [rospy.Publisher(f"/apart/rgbd_image{i}", RGBDImage, queue_size=10) for i in range(2)]
        # Outputs subscribed, so the nodes would publish if a set came out.
        self.outs = []
        self.subs = [rospy.Subscriber("/missing/rgbd_image", RGBDImage, self.outs.append),
                     rospy.Subscriber("/apart/rgbd_images", RGBDImages, self.outs.append)]

    def warnings(self, node):
        """The node's warnings issued after data flowed (the first may precede our first message)."""
        return [m.msg for m in self.log.find(Log.WARN, WARNING, "received, last stamp") if m.msg.startswith(node)]

    def test_warning_lists_topics_policy_and_arrivals(self):
        sc.wait_connected(self, [self.rgb, self.info] + self.cams, self.subs)
        start = time.time()
        i = 0
        while time.time() - start < 25.0 and not (self.warnings("/missing/rgbd_sync") and
                                                   self.warnings("/apart/rgbdx_sync")):
            t = rospy.Time(500) + rospy.Duration(0.1 * i)
            self.rgb.publish(sc.image(t, "bgr8", i))
            self.info.publish(sc.camera_info(t))
            self.cams[0].publish(sc.rgbd_image(t, i))
            self.cams[1].publish(sc.rgbd_image(t + rospy.Duration(0.03), i))  # never the same stamp
            i += 1
            time.sleep(0.1)
        self.assertEqual(self.outs, [], "a set came out although it should not")

        missing = self.warnings("/missing/rgbd_sync")
        self.assertTrue(missing, f"no warning from rgbd_sync within 25 s; log: {[m.msg for m in self.log.lines]}")
        text = missing[0]
        self.assertIn("(approx sync, queue 10, max interval 0.020 s)", text)
        self.assertRegex(text, r"\n   /missing/rgb/image \[sensor_msgs/Image\]: \d+ received, last stamp 5\d\d\.")
        self.assertIn("\n   /missing/depth/image [sensor_msgs/Image]: nothing received", text)
        self.assertRegex(text, r"\n   /missing/rgb/camera_info \[sensor_msgs/CameraInfo\]: \d+ received")
        self.assertIn("Make sure every topic above is published", text)

        apart = self.warnings("/apart/rgbdx_sync")
        self.assertTrue(apart, "no warning from rgbdx_sync within 25 s")
        text = apart[0]
        self.assertIn("(exact sync, queue 5)", text)
        for cam in range(2):
            self.assertRegex(text, rf"\n   /apart/rgbd_image{cam} \[rtabmap_ros/RGBDImage\]: \d+ received")
        self.assertIn("too far apart for the sync policy", text)


if __name__ == "__main__":
    rospy.init_node("sync_missing_topic_check")
    rostest.rosrun("rtabmap_ros", "sync_missing_topic", MissingTopic, sys.argv)
