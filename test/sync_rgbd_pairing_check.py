#!/usr/bin/python3
"""Checks sync_rgbd_pairing.test: which synthetic frames rgbd_sync pairs and which it drops.

Frames come every 100 ms; rgb and camera_info carry the frame's stamp, depth comes a few
milliseconds later (as from a real sensor) or not at all. Every image names its frame (rgb
bytes = i, depth = 1000 + i mm), so a wrong pairing shows in the output."""
import sys
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import RGBDImage
from sensor_msgs.msg import CameraInfo, Image

import sync_common as sc

PERIOD = 0.1
# Frame kinds, in publishing order. "good": depth 5 ms after rgb; "late": depth 12 ms after.
KINDS = (["good"] * 3 + ["no_depth", "good", "far_depth", "good", "late", "no_depth", "no_depth", "good",
                         "empty_rgb", "good", "small_depth", "good", "zero_k", "good", "bad_encoding", "good",
                         "duplicate", "good", "out_of_order", "good"] + ["good"] * 4)
PAIRED = {"good", "late"}
TAIL = 3  # the last sets may stay in the synchroniser's queue (it waits for later messages)


class RgbdPairing(unittest.TestCase):
    def setUp(self):
        self.log = sc.RosoutLog()
        self.rgb = rospy.Publisher("/rgb/image", Image, queue_size=100)
        self.depth = rospy.Publisher("/depth/image", Image, queue_size=100)
        self.info = rospy.Publisher("/rgb/camera_info", CameraInfo, queue_size=100)
        self.out = []
        self.sub = rospy.Subscriber("/rgbd_image", RGBDImage, self.out.append, queue_size=100)

    def publish(self, i, kind, t):
        rgb = sc.image(t, "bgr8", i)
        depth = sc.image(t + rospy.Duration(0.012 if kind == "late" else 0.005), "16UC1", 1000 + i)
        info = sc.camera_info(t)
        if kind == "empty_rgb":
            rgb.width = rgb.height = rgb.step = 0
            rgb.data = b""
        elif kind == "small_depth":
            depth = sc.image(depth.header.stamp, "16UC1", 1000 + i, w=sc.W // 2, h=sc.H // 2)
        elif kind == "zero_k":
            info.K = [0.0] * 9
            info.P = [0.0] * 12
        elif kind == "bad_encoding":
            depth = sc.image(depth.header.stamp, "8UC3", 7)
        elif kind == "far_depth":
            depth.header.stamp = t + rospy.Duration(0.045)
        elif kind in ("duplicate", "out_of_order"):
            # The previous good frame again (same stamps), or one from 0.5 s ago: dropped
            # before the synchroniser, never paired.
            back = rospy.Duration(PERIOD if kind == "duplicate" else 0.5)
            rgb.header.stamp = info.header.stamp = t - back
            depth.header.stamp = t - back + rospy.Duration(0.005)
        self.rgb.publish(rgb)
        self.info.publish(info)
        if kind != "no_depth":
            self.depth.publish(depth)

    def test_pairs_approximate_stamps_and_drops_the_rest(self):
        sc.wait_connected(self, [self.rgb, self.depth, self.info], [self.sub, self.log.sub])
        stamps = [rospy.Time(1000) + rospy.Duration(PERIOD * i) for i in range(len(KINDS))]
        for i, kind in enumerate(KINDS):
            self.publish(i, kind, stamps[i])
            time.sleep(0.04)
        expected = [i for i, k in enumerate(KINDS[:-TAIL]) if k in PAIRED]
        sc.wait_for(lambda: len(self.out) >= len(expected), 10.0)
        time.sleep(0.5)

        got = []
        for m in self.out:
            self.assertIn(m.header.stamp, stamps, "output stamp is not an rgb stamp")
            i = stamps.index(m.header.stamp)
            got.append(i)
            self.assertEqual(m.rgb.data[0], i, f"frame {i}: rgb of another frame")
            self.assertTrue((sc.depth_values(m.depth) == 1000 + i).all(), f"frame {i}: paired with another depth")
        self.assertEqual(len(got), len(set(got)), f"a frame came out twice: {got}")
        self.assertEqual([i for i in got if i < len(KINDS) - TAIL], expected,
                         f"paired {got}, expected {expected} (kinds {KINDS})")
        # Bad frames: a clear error each, naming the topic and the problem.
        for words in (("rgb/image",), ("depth/image is 32x24 but rgb/image is 64x48",), ("rgb/camera_info",),
                      ("depth/image", "8UC3"), ("duplicated",), ("out of order",)):
            self.assertTrue(self.log.find(Log.ERROR, *words), f"no error mentioning {words} in the log: "
                            f"{[m.msg for m in self.log.lines if m.level >= Log.WARN]}")


if __name__ == "__main__":
    rospy.init_node("sync_rgbd_pairing_check")
    rostest.rosrun("rtabmap_ros", "sync_rgbd_pairing", RgbdPairing, sys.argv)
