#!/usr/bin/python3
"""Checks sync_nodelets.test: in each namespace (a manager, standalone nodes), rgbd_sync,
stereo_sync and rgbdx_sync publish what their classic counterparts do for synthetic input."""
import sys
import time
import unittest

import rospy
import rostest
from rtabmap_ros.msg import RGBDImage, RGBDImages
from sensor_msgs.msg import CameraInfo, Image

import sync_common as sc

BASELINE = 0.1
FRAMES = 15


class SyncNodelets(unittest.TestCase):
    def setUp(self):
        self.cameras = rospy.get_param("~namespaces")  # namespace -> rgbdx_sync cameras
        self.pubs, self.subs, self.got = {}, [], {}
        for ns, n in self.cameras.items():
            p = lambda topic, t: rospy.Publisher(f"/{ns}/{topic}", t, queue_size=50)
            self.pubs[ns] = {
                "rgb": p("rgb/image", Image), "depth": p("depth/image", Image),
                "info": p("rgb/camera_info", CameraInfo),
                "left": p("left/image_rect", Image), "right": p("right/image_rect", Image),
                "left_info": p("left/camera_info", CameraInfo), "right_info": p("right/camera_info", CameraInfo),
                "rgbd": [p(f"rgbd_image{i}", RGBDImage) for i in range(n)],
            }
            for key, topic, t in (("rgbd", "rgbd_image", RGBDImage), ("stereo", "stereo/rgbd_image", RGBDImage),
                                  ("rgbdx", "rgbd_images", RGBDImages), ("compressed", "rgbd_image/compressed", RGBDImage)):
                self.got[(ns, key)] = []
                self.subs.append(rospy.Subscriber(f"/{ns}/{topic}", t,
                                                  lambda m, k=(ns, key): self.got[k].append(m)))

    def publishers(self):
        for pubs in self.pubs.values():
            for v in pubs.values():
                yield from (v if isinstance(v, list) else [v])

    def test_each_nodelet_in_manager_and_as_node(self):
        sc.wait_connected(self, list(self.publishers()), self.subs)
        sent = []
        for i in range(FRAMES):
            t = rospy.Time(100 + i * 0.1)
            sent.append(t)
            for ns, p in self.pubs.items():
                # rgbd_sync (approx): depth 5 ms late. stereo_sync (exact): identical stamps.
                p["rgb"].publish(sc.image(t, "bgr8", i))
                p["depth"].publish(sc.image(t + rospy.Duration(0.005), "16UC1", 1000 + i))
                p["info"].publish(sc.camera_info(t))
                p["left"].publish(sc.image(t, "mono8", i))
                p["right"].publish(sc.image(t, "mono8", 100 + i))
                p["left_info"].publish(sc.camera_info(t, frame="left_optical"))
                p["right_info"].publish(sc.camera_info(t, tx=-sc.FX * BASELINE, frame="right_optical"))
                for c, pub in enumerate(p["rgbd"]):  # camera c is c ms late
                    pub.publish(sc.rgbd_image(t + rospy.Duration(0.001 * c), 10 * c + i))
            time.sleep(0.05)
        sc.wait_for(lambda: all(len(v) >= FRAMES - 3 for k, v in self.got.items() if k[1] != "compressed"), 10.0)
        for ns, n in self.cameras.items():
            self.check_rgbd_and_stereo(ns, sent)
            self.check_rgbdx(ns, n, sent)
        self.check_compressed(self.got[("managed", "compressed")], sent, rate=4.0)
        self.check_compressed(self.got[("node", "compressed")], sent, rate=0.0)

    def check_compressed(self, msgs, sent, rate):
        """rgbd_image/compressed: jpeg colour and compressedDepth, at most `rate` Hz of data time."""
        expected = (FRAMES - 3) // 3 if rate > 0 else FRAMES - 3  # 0.1 s frames, one in 3 at 4 Hz
        self.assertGreaterEqual(len(msgs), expected, f"{len(msgs)} compressed outputs (rate {rate})")
        for m in msgs:
            self.assertIn(m.header.stamp, sent)
            self.assertEqual((len(m.rgb.data), len(m.depth.data)), (0, 0), "compressed output has raw images")
            self.assertIn("jpeg", m.rgb_compressed.format)
            self.assertIn("compressedDepth", m.depth_compressed.format)
            self.assertGreater(len(m.depth_compressed.data), 12)
        gaps = [(b.header.stamp - a.header.stamp).to_sec() for a, b in zip(msgs, msgs[1:])]
        if rate > 0:
            self.assertTrue(all(g >= 1.0 / rate - 1e-6 for g in gaps), f"compressed at more than {rate} Hz: {gaps}")

    def check_rgbd_and_stereo(self, ns, sent):
        rgbd, stereo = self.got[(ns, "rgbd")], self.got[(ns, "stereo")]
        for name, msgs in (("rgbd_sync", rgbd), ("stereo_sync", stereo)):
            self.assertGreaterEqual(len(msgs), FRAMES - 3, f"{ns}/{name}: {len(msgs)} outputs")
        for m in rgbd:
            i = sent.index(m.header.stamp)
            self.assertEqual(m.rgb.encoding, "bgr8")
            self.assertEqual(m.rgb.data[0], i, f"{ns}/rgbd_sync: rgb of another frame")
            self.assertTrue((sc.depth_values(m.depth) == 1000 + i).all(), f"{ns}/rgbd_sync: depth of another frame")
            self.assertAlmostEqual(m.rgb_camera_info.K[0], sc.FX, places=6)
        for m in stereo:
            i = sent.index(m.header.stamp)
            self.assertEqual((m.rgb.data[0], m.depth.data[0]), (i, 100 + i), f"{ns}/stereo_sync: wrong pair")
            self.assertEqual(m.depth.encoding, "mono8")
            self.assertAlmostEqual(-m.depth_camera_info.P[3] / m.depth_camera_info.P[0], BASELINE, places=6)
            self.assertEqual(m.depth_camera_info.header.frame_id, "right_optical")

    def check_rgbdx(self, ns, n, sent):
        msgs = self.got[(ns, "rgbdx")]
        self.assertGreaterEqual(len(msgs), FRAMES - 3, f"{ns}/rgbdx_sync: {len(msgs)} outputs")
        for m in msgs:
            i = sent.index(m.header.stamp)  # camera 0's stamp
            self.assertEqual(len(m.rgbd_images), n, f"{ns}/rgbdx_sync")
            for c, cam in enumerate(m.rgbd_images):
                self.assertEqual(cam.rgb.data[0], 10 * c + i, f"{ns}/rgbdx_sync: camera {c} of another frame")
                self.assertEqual(cam.header.stamp, sent[i] + rospy.Duration(0.001 * c))


if __name__ == "__main__":
    rospy.init_node("sync_nodelets_check")
    rostest.rosrun("rtabmap_ros", "sync_nodelets", SyncNodelets, sys.argv)
