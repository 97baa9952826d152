#!/usr/bin/python3
"""Checks that every rgbd_sync instance of nodelet_plumbing.test publishes synchronised
RGBDImage messages with its parameters applied (decimation, depth_scale, exact/approx sync)."""
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
from rtabmap_ros.msg import RGBDImage
from sensor_msgs.msg import CameraInfo, Image

W, H = 64, 48
FX, CX, CY = 50.0, 32.0, 24.0


def make_images(stamp, depth_offset):
    rgb = Image()
    rgb.header.stamp = stamp
    rgb.header.frame_id = "camera_optical"
    rgb.height, rgb.width, rgb.encoding, rgb.step = H, W, "bgr8", W * 3
    rgb.data = (np.arange(W * H * 3) % 251).astype(np.uint8).tobytes()
    depth = Image()
    depth.header.stamp = stamp + rospy.Duration(depth_offset)
    depth.header.frame_id = "camera_optical"
    depth.height, depth.width, depth.encoding, depth.step = H, W, "16UC1", W * 2
    depth.data = np.full(W * H, 1000, dtype=np.uint16).tobytes()  # 1 m everywhere
    info = CameraInfo()
    info.header = rgb.header
    info.width, info.height = W, H
    info.K = [FX, 0, CX, 0, FX, CY, 0, 0, 1]
    info.P = [FX, 0, CX, 0, 0, FX, CY, 0, 0, 0, 1, 0]
    return rgb, depth, info


class NodeletPlumbing(unittest.TestCase):
    def setUp(self):
        self.received = {}
        self.pubs = {}
        self.subs = []
        for ns in rospy.get_param("~namespaces"):
            self.received[ns] = []
            self.pubs[ns] = (rospy.Publisher(f"/{ns}/rgb/image", Image, queue_size=5),
                             rospy.Publisher(f"/{ns}/depth/image", Image, queue_size=5),
                             rospy.Publisher(f"/{ns}/rgb/camera_info", CameraInfo, queue_size=5))
            self.subs.append(rospy.Subscriber(f"/{ns}/rgbd_image", RGBDImage,
                                              lambda m, ns=ns: self.received[ns].append(m)))

    def wait_connected(self, timeout=30.0):
        """Waits until each instance subscribes to our topics and we to its output."""
        end = time.time() + timeout
        while time.time() < end:
            ready = all(p.get_num_connections() > 0 for pubs in self.pubs.values() for p in pubs)
            ready = ready and all(s.get_num_connections() > 0 for s in self.subs)
            if ready:
                return
            time.sleep(0.1)
        missing = [ns for ns, pubs in self.pubs.items() if any(p.get_num_connections() == 0 for p in pubs)]
        self.fail(f"rgbd_sync did not come up (nodelet not loaded?) in: {missing}")

    def test_each_instance_publishes_synchronised_frames(self):
        self.wait_connected()
        sent = []
        for i in range(20):
            stamp = rospy.Time.now()
            sent.append(stamp)
            for ns, (rgb_pub, depth_pub, info_pub) in self.pubs.items():
                # The approx instances get depth 5 ms after rgb, as from a real sensor; the exact
                # instance needs identical stamps.
                rgb, depth, info = make_images(stamp, 0.0 if ns == "wrapped" else 0.005)
                rgb_pub.publish(rgb)
                depth_pub.publish(depth)
                info_pub.publish(info)
            time.sleep(0.05)
        end = time.time() + 10.0
        while time.time() < end and any(len(v) < 5 for v in self.received.values()):
            time.sleep(0.1)

        for ns, msgs in self.received.items():
            self.assertGreaterEqual(len(msgs), 5, f"{ns}: only {len(msgs)} RGBDImage received")
            for m in msgs:
                self.assertIn(m.header.stamp, sent, f"{ns}: stamp is not an rgb stamp")
                decimation = 2 if ns == "standalone" else 1
                self.assertEqual((m.rgb.width, m.rgb.height), (W // decimation, H // decimation), ns)
                self.assertEqual((m.depth.width, m.depth.height), (W // decimation, H // decimation), ns)
                self.assertAlmostEqual(m.rgb_camera_info.K[0], FX / decimation, places=5, msg=ns)
                self.assertAlmostEqual(m.rgb_camera_info.K[2], CX / decimation, places=5, msg=ns)
                depth = np.frombuffer(m.depth.data, dtype=np.uint16)
                expected = 2000 if ns == "standalone" else 1000  # depth_scale 2 on standalone
                self.assertTrue(np.all(depth == expected), f"{ns}: depth {depth[:4]} != {expected}")


if __name__ == "__main__":
    rospy.init_node("nodelet_plumbing_check")
    rostest.rosrun("rtabmap_ros", "nodelet_plumbing", NodeletPlumbing, sys.argv)
