#!/usr/bin/python3
"""Checks odom_nodelets.test: in each namespace (manager, standalone nodes) the three odometry
nodes answer their services, track a synthetic room scan, report textureless images as lost
(null pose, 9999 covariance), and survive bad input with a clear error."""
import math
import os
import select
import subprocess
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from rtabmap_ros.msg import RGBDImage
from rtabmap_ros.srv import ResetPose
from sensor_msgs.msg import CameraInfo, Image, LaserScan
from std_srvs.srv import Empty

import odom_common as oc
import sync_common as sc

KINDS = ("rgbd", "rgbdi", "stereo", "icp")


def room_scan(stamp, frame="laser"):
    """A 360-beam scan from the centre of an 8 x 6 m room (the laser at the origin)."""
    m = LaserScan()
    m.header.stamp, m.header.frame_id = stamp, frame
    m.angle_min, m.angle_increment = -math.pi, 2 * math.pi / 360
    m.angle_max = m.angle_min + 359 * m.angle_increment
    m.range_min, m.range_max = 0.1, 20.0
    for i in range(360):
        a = m.angle_min + i * m.angle_increment
        c, s = math.cos(a), math.sin(a)
        m.ranges.append(min(4.0 / abs(c) if abs(c) > 1e-9 else 1e9, 3.0 / abs(s) if abs(s) > 1e-9 else 1e9))
    return m


def textured_rgbd_image(stamp):
    """A 320 x 240 camera facing a wall 1.5 m away painted with random 8-pixel blocks (the
    same every frame: a still camera), as an rgbd_image."""
    w, h = 320, 240
    blocks = np.random.default_rng(7).integers(0, 256, size=(h // 8, w // 8), dtype=np.uint8)
    grey = np.kron(blocks, np.ones((8, 8), dtype=np.uint8))
    m = sc.rgbd_image(stamp, 0)
    m.rgb = sc.image(stamp, "mono8", 0, w=w, h=h)
    m.rgb.data = grey.tobytes()
    m.depth = sc.image(stamp, "16UC1", 1500, w=w, h=h)
    info = sc.camera_info(stamp, fx=250.0)
    info.width, info.height = w, h
    info.K = [250.0, 0, w / 2, 0, 250.0, h / 2, 0, 0, 1]
    info.P = [250.0, 0, w / 2, 0, 0, 250.0, h / 2, 0, 0, 0, 1, 0]
    m.rgb_camera_info = m.depth_camera_info = info
    return m


def nan_depth(msg):
    """The rgbd_image with a 32FC1 depth image where every pixel is NaN (no depth anywhere)."""
    d = msg.depth
    d.encoding, d.step = "32FC1", d.width * 4
    d.data = np.full(d.width * d.height, np.nan, dtype=np.float32).tobytes()
    return msg


def mounting(child, x, y, z, qx, qy, qz, qw):
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = "base_link", child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = qx, qy, qz, qw
    return t


class OdomNodelets(unittest.TestCase):
    def setUp(self):
        # Laser 0.1 m ahead; cameras 0.5 m up, looking forward (optical: z forward, x right, y down).
        self.static_tf = tf2_ros.StaticTransformBroadcaster()
        self.static_tf.sendTransform([mounting("laser", 0.1, 0, 0.2, 0, 0, 0, 1),
                                      mounting("camera_optical", 0, 0, 0.5, -0.5, 0.5, -0.5, 0.5),
                                      mounting("left_optical", 0, 0, 0.5, -0.5, 0.5, -0.5, 0.5)])
        self.namespaces = rospy.get_param("~namespaces")
        self.log = sc.RosoutLog()
        self.got = {}
        self.pubs = {}
        for ns in self.namespaces:
            p = lambda topic, t: rospy.Publisher(f"/{ns}/{topic}", t, queue_size=20)
            self.pubs[ns] = {"rgb": p("rgbd/rgb/image", Image), "depth": p("rgbd/depth/image", Image),
                             "info": p("rgbd/rgb/camera_info", CameraInfo),
                             "left": p("stereo/left/image_rect", Image), "right": p("stereo/right/image_rect", Image),
                             "left_info": p("stereo/left/camera_info", CameraInfo),
                             "right_info": p("stereo/right/camera_info", CameraInfo), "scan": p("icp/scan", LaserScan),
                             "rgbdi": p("rgbdi/rgbd_image", RGBDImage)}
            for kind in KINDS:
                self.got[(ns, kind)] = []
                rospy.Subscriber(f"/{ns}/{kind}/odom", Odometry, lambda m, k=(ns, kind): self.got[k].append(m))

    def send(self, ns, t, value=0, zero_k=False, scan=None):
        p = self.pubs[ns]
        info = sc.camera_info(t)
        if zero_k:
            info.K = [0.0] * 9
            info.P = [0.0] * 12
        p["rgb"].publish(sc.image(t, "bgr8", value))
        p["depth"].publish(sc.image(t, "16UC1", 1000))
        p["info"].publish(info)
        p["left"].publish(sc.image(t, "mono8", value))
        p["right"].publish(sc.image(t, "mono8", value))
        p["left_info"].publish(sc.camera_info(t, frame="left_optical"))
        p["right_info"].publish(sc.camera_info(t, tx=-sc.FX * 0.1, frame="left_optical"))
        p["scan"].publish(scan if scan is not None else room_scan(t))
        p["rgbdi"].publish(textured_rgbd_image(t))

    def call_services(self, base):
        for name in ("reset_odom", "pause_odom", "resume_odom", "reset_odom_to_pose"):
            rospy.wait_for_service(base + name, timeout=30)
        rospy.ServiceProxy(base + "pause_odom", Empty)()
        rospy.ServiceProxy(base + "resume_odom", Empty)()
        rospy.ServiceProxy(base + "reset_odom", Empty)()
        rospy.ServiceProxy(base + "reset_odom_to_pose", ResetPose)(x=1.0, y=2.0, z=0, roll=0, pitch=0, yaw=0)

    def startup_lines(self, name, params, expected):
        """Starts icp_odometry as its own node (launch-time lines came before this check could
        listen) with private `params`, and returns what it printed once every `expected` line
        came, or after 30 s."""
        node = subprocess.Popen(["rosrun", oc.PKG, "icp_odometry", "__name:=" + name, "__ns:=/" + name] +
                                ["_%s:=%s" % kv for kv in params],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED="1"))  # INFO: stdout
        text = ""
        try:
            end = time.time() + 30
            while time.time() < end and not all(e in text for e in expected):
                ready, _, _ = select.select([node.stdout], [], [], 0.5)
                if ready:
                    line = node.stdout.readline()
                    if not line:
                        break
                    text += line
        finally:
            node.terminate()
            node.wait(timeout=10)
        return text

    def misspelled_parameters(self):
        """A node started with misspelled keys warns naming each and the closest one."""
        expected = ['unknown parameter "Odom/Stratgy" ignored (did you mean "Odom/Strategy"?)',
                    'unknown parameter "odom_frameid" ignored (did you mean "odom_frame_id"?)',
                    '"Icp/VoxelSize" = "-1" ignored']
        text = self.startup_lines("typo", [("Odom/Stratgy", 1), ("odom_frameid", "odom2"), ("Icp/VoxelSize", -1)],
                                  expected)
        for e in expected:
            self.assertIn(e, text)

    def config_path(self):
        """config_path: the INI's core parameters reach the odometry (Odom/Strategy 1: scan to
        scan), private parameters override them, and a missing file is an error the node
        survives with the defaults (scan to map)."""
        ini = os.path.join(oc.workdir(self, "odom_config_"), "odom.ini")
        with open(ini, "w") as f:
            f.write("[Core]\nOdom/Strategy = 1\n")
        text = self.startup_lines("ini", [("config_path", ini)], ["S2S odometry"])
        self.assertIn("1 core parameters from " + ini, text)
        self.assertIn("S2S odometry", text)
        text = self.startup_lines("ini_overridden", [("config_path", ini), ("Odom/Strategy", 0)], ["S2M odometry"])
        self.assertIn("S2M odometry", text)
        missing = ini + ".missing"
        text = self.startup_lines("ini_missing", [("config_path", missing)], ["S2M odometry"])
        self.assertIn("config_path: ", text)
        self.assertIn(missing, text)
        self.assertIn("the file is ignored", text)
        self.assertIn("S2M odometry", text)

    def test_each_nodelet(self):
        pubs = [p for d in self.pubs.values() for p in d.values()]
        end = time.time() + 30
        while time.time() < end and not all(p.get_num_connections() > 0 for p in pubs):
            time.sleep(0.1)
        missing = [p.resolved_name for p in pubs if p.get_num_connections() == 0]
        self.assertFalse(missing, f"odometry nodes did not subscribe (not loaded?): {missing}")

        # 10 frames at 10 Hz, and up to 4 more while some node has not yet updated 8 times: a
        # node busy with its previous frame drops the next (queue_size), which on a loaded machine
        # is not a failure. The stamps stay below the bad input's below (101.5).
        def enough():
            return all(len(self.got[(ns, k)]) >= 8 for ns in self.namespaces for k in ("icp", "rgbdi"))
        for i in range(14):
            if i >= 10 and enough():
                break
            t = rospy.Time(100 + i * 0.1)
            for ns in self.namespaces:
                self.send(ns, t, value=50)
            time.sleep(0.1)
        for ns in self.namespaces:
            key = (ns, "icp")
            self.assertTrue(oc.wait_for(lambda: len(self.got[key]) >= 8, 20), f"{key}: {len(self.got[key])} updates")
            m = self.got[key][-1]
            self.assertFalse(oc.lost(m), "a static room scan must be tracked")
            self.assertLess(math.hypot(m.pose.pose.position.x, m.pose.pose.position.y), 0.05)
            cov = m.pose.covariance
            self.assertTrue(0 < cov[0] < 9999 and 0 < cov[35] < 9999, f"covariance {cov}")
            key = (ns, "rgbdi")
            self.assertTrue(oc.wait_for(lambda: len(self.got[key]) >= 8, 20), f"{key}: {len(self.got[key])} updates")
            m = self.got[key][-1]
            self.assertFalse(oc.lost(m), "a still camera facing a textured wall must be tracked")
            self.assertLess(math.hypot(m.pose.pose.position.x, m.pose.pose.position.y), 0.05)
            for cam in ("rgbd", "stereo"):
                k = (ns, cam)
                self.assertTrue(oc.wait_for(lambda: len(self.got[k]) >= 5, 20), f"{k}: {len(self.got[k])} updates")
                m = self.got[k][-1]
                self.assertTrue(oc.lost(m), f"{k}: textureless images must be lost, got {m.pose}")
                self.assertEqual(m.pose.pose.orientation.w, 0.0, "lost: null pose")
                self.assertEqual(m.pose.covariance[35], 9999.0)

        # Bad input: zero K, a scan whose ranges are all NaN, a scan in a frame tf does not know.
        nan_scan = room_scan(rospy.Time(101.5))
        nan_scan.ranges = [float("nan")] * len(nan_scan.ranges)
        unknown = room_scan(rospy.Time(101.6), frame="nowhere")
        # Then an empty rgb image, a depth image of NaN, and a scan stamped before the previous one.
        for ns in self.namespaces:
            self.send(ns, rospy.Time(101.5), zero_k=True, scan=nan_scan)
            self.send(ns, rospy.Time(101.6), scan=unknown)
            empty = sc.image(rospy.Time(101.7), "bgr8", 0, w=0, h=0)
            self.pubs[ns]["rgb"].publish(empty)
            self.pubs[ns]["depth"].publish(sc.image(rospy.Time(101.7), "16UC1", 1000))
            self.pubs[ns]["info"].publish(sc.camera_info(rospy.Time(101.7)))
            self.pubs[ns]["scan"].publish(room_scan(rospy.Time(101.0)))
            self.pubs[ns]["rgbdi"].publish(nan_depth(textured_rgbd_image(rospy.Time(101.8))))
        error = 8  # rosgraph_msgs/Log.ERROR
        for words in (("rgbd_odometry", "camera_info"), ("icp_odometry", "scan", "101.5"),
                      ("icp_odometry", "nowhere"), ("rgbd_odometry", "rgb/image", "101.7"),
                      ("icp/scan", "out of order")):
            self.assertTrue(oc.wait_for(lambda: len(self.log.find(error, *words)) >= len(self.namespaces), 10),
                            f"no error with {words} from each node: {[m.msg for m in self.log.lines if m.level >= error]}")
        # NaN depth is no depth: the frame is processed (tracked on its 2D features against the
        # map, or lost), never an exception.
        for ns in self.namespaces:
            k = (ns, "rgbdi")
            self.assertTrue(oc.wait_for(lambda: any(m.header.stamp == rospy.Time(101.8) for m in self.got[k]), 10),
                            f"{k}: no odometry for the NaN depth frame")
        self.misspelled_parameters()
        self.config_path()

        # Still running: every service answers, and the reset pose is where tracking restarts.
        for ns in self.namespaces:
            for kind in KINDS:
                self.call_services(f"/{ns}/{kind}/")
            n = len(self.got[(ns, "icp")])
            for i in range(3):
                self.send(ns, rospy.Time(102 + i * 0.1), value=50)
                time.sleep(0.1)
            self.assertTrue(oc.wait_for(lambda: len(self.got[(ns, "icp")]) >= n + 2, 10), f"{ns}: icp stopped")
            p = self.got[(ns, "icp")][-1].pose.pose.position
            self.assertAlmostEqual(p.x, 1.0, delta=0.05)
            self.assertAlmostEqual(p.y, 2.0, delta=0.05)


if __name__ == "__main__":
    rospy.init_node("odom_nodelets_check")
    rostest.rosrun(oc.PKG, "odom_nodelets", OdomNodelets, sys.argv)
