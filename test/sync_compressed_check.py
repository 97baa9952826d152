#!/usr/bin/python3
"""Checks sync_compressed.test: compressed and compressedDepth inputs of the sync nodelets."""
import struct
import sys
import time
import unittest

import cv2
import numpy as np
import rospy
import rostest
from rosgraph_msgs.msg import Log
from rtabmap_ros.msg import RGBDImage
from sensor_msgs.msg import CameraInfo, CompressedImage

W, H = 64, 48


def info(stamp, frame, tx=0.0):
    m = CameraInfo()
    m.header.stamp, m.header.frame_id = stamp, frame
    m.width, m.height = W, H
    m.K = [50.0, 0, 32.0, 0, 50.0, 24.0, 0, 0, 1]
    m.P = [50.0, 0, 32.0, tx, 0, 50.0, 24.0, 0, 0, 0, 1, 0]
    return m


def compressed(stamp, fmt, data):
    m = CompressedImage()
    m.header.stamp, m.header.frame_id = stamp, "cam"
    m.format, m.data = fmt, data
    return m


class SyncCompressed(unittest.TestCase):
    def setUp(self):
        self.rgbd, self.stereo, self.logs = [], [], []
        rospy.Subscriber("/rgbd_image", RGBDImage, self.rgbd.append)
        rospy.Subscriber("/stereo/rgbd_image", RGBDImage, self.stereo.append)
        rospy.Subscriber("/rosout", Log, self.logs.append)
        self.color = rospy.Publisher("/cam/color/compressed", CompressedImage, queue_size=5)
        self.depth = rospy.Publisher("/cam/depth/compressedDepth", CompressedImage, queue_size=5)
        self.color_info = rospy.Publisher("/cam/color_info", CameraInfo, queue_size=5)
        self.left = rospy.Publisher("/stereo/left/compressed", CompressedImage, queue_size=5)
        self.right = rospy.Publisher("/stereo/right/compressed", CompressedImage, queue_size=5)
        self.left_info = rospy.Publisher("/stereo/left_info", CameraInfo, queue_size=5)
        self.right_info = rospy.Publisher("/stereo/right_info", CameraInfo, queue_size=5)
        pubs = [self.color, self.depth, self.color_info, self.left, self.right, self.left_info, self.right_info]
        end = time.time() + 20
        while time.time() < end and any(p.get_num_connections() == 0 for p in pubs):
            time.sleep(0.1)
        self.assertTrue(all(p.get_num_connections() > 0 for p in pubs),
                        "the sync nodes did not subscribe to the compressed topics")

    def test_compressed_inputs(self):
        rng = np.random.default_rng(3)
        sent = {}
        for i in range(10):
            stamp = rospy.Time.now()
            bgr = rng.integers(0, 255, (H, W, 3), dtype=np.uint8)
            depth = rng.integers(300, 5000, (H, W), dtype=np.uint16)
            sent[stamp] = (bgr, depth)
            self.color.publish(compressed(stamp, "bgr8; png compressed bgr8", cv2.imencode(".png", bgr)[1].tobytes()))
            header = struct.pack("<iff", 0, 0.0, 0.0)  # compressedDepth: format, quantisation A, B
            self.depth.publish(compressed(stamp, "16UC1; compressedDepth png",
                                          header + cv2.imencode(".png", depth)[1].tobytes()))
            self.color_info.publish(info(stamp, "cam"))
            grey = rng.integers(0, 255, (H, W), dtype=np.uint8)
            jpeg = cv2.imencode(".jpg", grey)[1].tobytes()
            self.left.publish(compressed(stamp, "mono8; jpeg compressed mono8", jpeg))
            self.right.publish(compressed(stamp, "mono8; jpeg compressed mono8", jpeg))
            self.left_info.publish(info(stamp, "left"))
            self.right_info.publish(info(stamp, "right", -5.0))
            if i == 4:
                # A corrupt colour image at its own stamp: dropped with an error, nothing else lost.
                bad = stamp + rospy.Duration(0.01)
                self.color.publish(compressed(bad, "bgr8; png compressed bgr8", b"\x89PNG broken"))
            time.sleep(0.1)
        end = time.time() + 10
        while time.time() < end and (len(self.rgbd) < 10 or len(self.stereo) < 10):
            time.sleep(0.1)

        self.assertEqual(len(self.rgbd), 10, "rgbd_sync: %d of 10 frames" % len(self.rgbd))
        for m in self.rgbd:
            bgr, depth = sent[m.header.stamp]
            rgb = m.rgb if m.rgb.data else None
            self.assertIsNotNone(rgb, "rgbd_image without its raw rgb")
            self.assertEqual(rgb.encoding, "bgr8")
            self.assertTrue(np.array_equal(np.frombuffer(rgb.data, np.uint8).reshape(H, W, 3), bgr), "rgb changed")
            self.assertEqual(m.depth.encoding, "16UC1")
            self.assertTrue(np.array_equal(np.frombuffer(m.depth.data, np.uint16).reshape(H, W), depth),
                            "depth changed (compressedDepth png is lossless)")
        self.assertGreaterEqual(len(self.stereo), 10, "stereo_sync: %d of 10 frames" % len(self.stereo))
        self.assertEqual((self.stereo[0].rgb.width, self.stereo[0].rgb.height), (W, H))
        errors = [l.msg for l in self.logs if l.level == Log.ERROR and "/cam/color/compressed" in l.msg]
        self.assertTrue(errors, "no error about the corrupt compressed image")
        self.assertIn("cannot decode", errors[0])


if __name__ == "__main__":
    rospy.init_node("sync_compressed_check")
    rostest.rosrun("rtabmap_ros", "sync_compressed", SyncCompressed, sys.argv)
